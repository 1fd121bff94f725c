#pragma once
// The sliding window of the SLAM backend: keyframe states, landmarks (inverse depth along the
// bearing seen by their anchor keyframe, one scalar each, so that the landmark block of the
// normal equations is diagonal), the marginalization prior, and the increments the LM solver
// applies.
//
// Keyframe state, in this order (its "tangent" coordinates dx):
//   p (3, world)  theta (3, right perturbation R <- R Exp(theta))  [v (3)  ba (3)  bg (3)]
// 6 values without an IMU, 15 with one.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <vector>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/slam/preintegration.hpp"
#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::backend::slam {

struct KeyframeState {
  std::int64_t id = 0;
  std::int64_t t_ns = 0;
  std::size_t frame_index = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< R_world_body
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      ///< body position in the world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();      ///< world velocity (IMU only)
  Eigen::Vector3d ba = Eigen::Vector3d::Zero();     ///< accelerometer bias (IMU only)
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();     ///< gyroscope bias (IMU only)
  std::vector<frontend::Feature> features;          ///< what the frontend saw (for the map)
  std::optional<Preintegration> imu_from_previous;  ///< previous keyframe -> this one

  Eigen::Isometry3d T_world_body() const;
  /// A copy with the navigation state only (no features, no preintegration).
  KeyframeState navigation_state() const;
  /// x <- x [+] dx for the first `dim` tangent coordinates (6 or 15).
  void apply_increment(const Eigen::VectorXd& dx, int dim);
  /// dx = x [-] x0 for the first `dim` tangent coordinates.
  Eigen::VectorXd difference(const KeyframeState& x0, int dim) const;
};

struct Observation {
  std::int64_t keyframe_id = 0;
  Eigen::Vector2d left = Eigen::Vector2d::Zero();  ///< rectified left pixel
  std::optional<Eigen::Vector2d> right;            ///< rectified right pixel (stereo match)
  bool inlier = true;
};

struct Landmark {
  std::int64_t track_id = 0;   ///< frontend track id (key within the window)
  std::int64_t map_id = 0;     ///< id in the saved map (unique over the run)
  std::int64_t anchor_id = 0;  ///< keyframe whose left camera holds the bearing
  Eigen::Vector3d bearing = Eigen::Vector3d::UnitZ();  ///< (x, y, 1) in the anchor left camera
  double inverse_depth = 1.0;                          ///< rho = 1 / z in the anchor left camera
  std::array<std::uint8_t, 32> descriptor{};
  std::vector<Observation> observations;  ///< the anchor's first

  int inlier_count() const;
};

/// Linear prior on some keyframe states, and on the disparity offset when has_offset, from
/// marginalization (or the initial gauge prior):
///   r(x) = r0 + J (x [-] x0),  x = [keyframe states in keyframe_ids order | delta],
///   cost 1/2 |r|^2.
struct Prior {
  std::vector<std::int64_t> keyframe_ids;
  std::vector<KeyframeState> linearization_points;  ///< x0, one per id
  bool has_offset = false;             ///< the last column of J is the disparity offset delta
  double offset_linearization_px = 0;  ///< delta0
  Eigen::MatrixXd J;
  Eigen::VectorXd r0;
  bool empty() const { return keyframe_ids.empty() && !has_offset; }
};

struct Window {
  BackendCamera camera;
  int state_dim = 6;  ///< 6 visual-only, 15 with IMU
  Eigen::Vector3d gravity{0, 0, -9.81};
  std::deque<KeyframeState> keyframes;
  std::map<std::int64_t, Landmark> landmarks;  ///< by track id
  Prior prior;
  /// Estimated stereo disparity offset delta (px): the right image is predicted at
  /// pi(P - b e_x) + (delta, 0) (SlamOptions::estimate_disparity_offset; 0 when not estimated).
  double disparity_offset_px = 0;

  /// Position of a keyframe id in the deque, or -1.
  int slot(std::int64_t keyframe_id) const;
  const KeyframeState& keyframe(std::int64_t keyframe_id) const;
  /// x [-] x0 of the prior's variables: [x_k [-] x0_k per prior keyframe | delta - delta0].
  Eigen::VectorXd prior_difference() const;
  /// World position of a landmark: p_w = R_a (R_bc bearing / rho + t_bc) + p_a.
  Eigen::Vector3d landmark_world(const Landmark& landmark) const;
};

}  // namespace edx::backend::slam
