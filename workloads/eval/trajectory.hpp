#pragma once
// A trajectory read from a file: stamped rigid poses in the order of the file, with the line each
// came from so that later checks can still name it.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace edx::eval {

/// A pose T = [R | t] (world <- body) kept exactly as read: R is checked to be orthonormal within a
/// tolerance but never re-orthonormalised, and inverses are general (R^-1, not R^T), so that
/// figures match tools that work on the raw 4x4 matrices.
using Pose = Eigen::Affine3d;

/// How the poses of a trajectory are keyed, and so how two trajectories are associated.
enum class StampKind {
  kFrameIndex,  ///< KITTI: an explicit frame index, or the ordinal of the pose in the file
  kSeconds,     ///< TUM, EuRoC: a timestamp in seconds
};

struct StampedPose {
  double time_s = 0.0;           ///< timestamp (s); for kFrameIndex equal to frame_index
  std::int64_t frame_index = 0;  ///< explicit frame index, or the ordinal of the pose in the file
  Pose pose = Pose::Identity();
  std::size_t line = 0;  ///< 1-based line of the source file
};

struct Trajectory {
  std::string source;  ///< the file name used in error messages
  StampKind stamp_kind = StampKind::kFrameIndex;
  std::vector<StampedPose> poses;  ///< strictly increasing frame_index (kFrameIndex) or time_s
  /// Rows dropped because their stamp repeated the previous row's (the first of each run of
  /// equal stamps is kept; docs/EVAL.md), and the line of the first one (0: none).
  std::size_t repeated_stamps_dropped = 0;
  std::size_t first_repeated_line = 0;
};

}  // namespace edx::eval
