#pragma once
// The two worlds of the four scenarios, each built from a seed: an indoor warehouse hall and an
// outdoor street grid. Each comes with the lane graph along which trajectories are planned (aisle
// or road centre lines) and the limits a vehicle keeps within it.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "workloads/datasets/synthetic/world.hpp"

namespace edx::synthetic {

/// Centre lines of the free corridors: nodes at junctions, undirected edges along corridors.
struct LaneGraph {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::vector<int>> neighbours;

  void add_edge(int a, int b);
};

enum class MotionStyle { kDrone, kCar };

/// How vehicles move through a scene (used by the trajectory planner).
struct MotionLimits {
  MotionStyle style = MotionStyle::kDrone;
  double lane_offset_m = 0;     ///< drive this far right of the centre line (car: right lane)
  double lateral_wander_m = 0;  ///< max smooth sideways deviation (drone)
  double min_height_m = 0;      ///< body height band (car: min = max)
  double max_height_m = 0;
  double cruise_speed_min = 0;  ///< m/s on straight corridors
  double cruise_speed_max = 0;
  double turn_speed = 0;     ///< m/s through junctions
  double turn_radius_m = 0;  ///< fillet radius of corners
  double max_accel = 0;      ///< m/s^2 along the path
  double clearance_m = 0;    ///< min distance of body and cameras to any geometry
};

struct Scene {
  World world;
  LaneGraph lanes;
  MotionLimits motion;
  bool outdoor = false;
};

/// Warehouse hall 44 x 26 x 9 m: five rows of pallet racks with cartons, pallets and labelled
/// beams; brick and metal-clad walls with posters; concrete floor with tape lines; ceiling with
/// lights. Lanes: the six aisles and the two cross aisles.
Scene build_warehouse(std::uint64_t seed);

/// Street grid of 4 x 4 blocks (3 x 3 junctions): facades with windows, shop fronts, sidewalks
/// with curbs, lamp posts, trees, crates and poster stands, parked cars, road markings and
/// crossings, open sky with clouds. Lanes: the road centre lines.
Scene build_street(std::uint64_t seed);

}  // namespace edx::synthetic
