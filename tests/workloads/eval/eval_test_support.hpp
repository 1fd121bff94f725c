#pragma once
// Helpers of the trajectory-evaluation tests: a scratch directory, trajectory builders and
// writers of KITTI / TUM / EuRoC files.
#include <fmt/core.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "workloads/eval/trajectory.hpp"

namespace edx::eval::testing {

/// A directory removed with everything in it when the test ends.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag)
      : path_(std::filesystem::temp_directory_path() /
              fmt::format("edx-eval-{}-{}", tag, ::getpid())) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  /// Writes `text` to `name` in the directory and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    const auto file = path_ / name;
    std::ofstream(file) << text;
    return file.string();
  }

 private:
  std::filesystem::path path_;
};

inline Pose make_pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& position) {
  Pose pose = Pose::Identity();
  pose.linear() = rotation;
  pose.translation() = position;
  return pose;
}

inline Eigen::Matrix3d rot_x(double rad) {
  return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
inline Eigen::Matrix3d rot_y(double rad) {
  return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
}
inline Eigen::Matrix3d rot_z(double rad) {
  return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// A frame-indexed trajectory (frames 0..n-1) from poses.
inline Trajectory frame_trajectory(const std::string& source, const std::vector<Pose>& poses) {
  Trajectory trajectory;
  trajectory.source = source;
  trajectory.stamp_kind = StampKind::kFrameIndex;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    StampedPose stamped;
    stamped.frame_index = static_cast<std::int64_t>(i);
    stamped.time_s = static_cast<double>(i);
    stamped.pose = poses[i];
    stamped.line = i + 1;
    trajectory.poses.push_back(stamped);
  }
  return trajectory;
}

/// A 3-D curve that moves along all three axes and turns (so that every alignment is well posed):
/// 60 poses along a helix with a rising, turning heading.
inline std::vector<Pose> helix_poses(std::size_t count = 60) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < count; ++i) {
    const double s = 0.1 * static_cast<double>(i);
    poses.push_back(make_pose(rot_z(0.5 * s) * rot_x(0.05 * s),
                              Eigen::Vector3d(5.0 * std::cos(s), 5.0 * std::sin(s), 0.3 * s)));
  }
  return poses;
}

/// One KITTI line "[frame ]r11 r12 r13 tx r21 ... tz" at full precision.
inline std::string kitti_line(const Pose& pose, long frame_index = -1) {
  std::string line = frame_index >= 0 ? fmt::format("{} ", frame_index) : std::string();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      line += fmt::format("{:.17g}{}", pose.matrix()(r, c), r == 2 && c == 3 ? "\n" : " ");
    }
  }
  return line;
}

/// One TUM line "t x y z qx qy qz qw".
inline std::string tum_line(double time_s, const Pose& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  return fmt::format("{:.9f} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n", time_s,
                     t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
}

}  // namespace edx::eval::testing
