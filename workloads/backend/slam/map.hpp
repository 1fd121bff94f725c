#pragma once
// The map the SLAM backend builds and the registration backend localizes against: keyframes
// (pose, keypoints with ORB descriptors) and landmarks (world position, descriptor, the
// keyframe keypoints that observed them), with the camera they were seen with.
//
// File format (save_map / load_map): JSON, {"format": "edx-slam-map", "version": 1, "source",
// "camera": {width, height, fx, fy, cx, cy, baseline_m, T_body_left: [tx ty tz qw qx qy qz]},
// "keyframes": [{id, t_ns, frame_index, T_world_body: [7], keypoints: [{track_id, left: [u, v],
// right: [u, v] | null, depth_m, octave, angle, descriptor: "64 hex digits"}]}],
// "landmarks": [{id, track_id, position: [x, y, z], descriptor, observations: [[keyframe_id,
// keypoint_index], ...]}]}. load_map validates every field and every reference and throws
// std::runtime_error "FILE: json.path: expected WHAT" on the first problem.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "workloads/backend/backend.hpp"

namespace edx::backend::slam {

inline constexpr int kMapFormatVersion = 1;
inline constexpr const char* kMapFormatName = "edx-slam-map";

using Descriptor = std::array<std::uint8_t, 32>;

struct MapKeypoint {
  std::int64_t track_id = 0;
  Eigen::Vector2d left = Eigen::Vector2d::Zero();  ///< rectified left pixel
  std::optional<Eigen::Vector2d> right;            ///< rectified right pixel (stereo match)
  double depth_m = 0;                              ///< stereo depth (0 without a match)
  int octave = 0;
  double angle_deg = 0;
  Descriptor descriptor{};
};

struct MapKeyframe {
  std::int64_t id = 0;
  std::int64_t t_ns = 0;
  std::size_t frame_index = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  std::vector<MapKeypoint> keypoints;
};

struct MapObservation {
  std::int64_t keyframe_id = 0;
  std::size_t keypoint_index = 0;
  bool operator==(const MapObservation&) const = default;
};

struct MapLandmark {
  std::int64_t id = 0;
  std::int64_t track_id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world frame, m
  Descriptor descriptor{};
  std::vector<MapObservation> observations;
};

struct Map {
  std::string source;                  ///< what built it (dataset name)
  BackendCamera camera;                ///< the camera of the keypoints
  std::vector<MapKeyframe> keyframes;  ///< by increasing id
  std::vector<MapLandmark> landmarks;  ///< by increasing id
};

/// Writes the map (see the file comment); throws std::runtime_error naming the file on failure.
void save_map(const Map& map, const std::filesystem::path& path);
/// Reads and validates a map file.
Map load_map(const std::filesystem::path& path);

}  // namespace edx::backend::slam
