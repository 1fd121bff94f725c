#include "workloads/datasets/kitti_dataset.hpp"

#include <fmt/core.h>
#include <spdlog/spdlog.h>

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

#include "workloads/datasets/image_io.hpp"
#include "workloads/datasets/rotation_check.hpp"
#include "workloads/datasets/text_table.hpp"
#include "workloads/eval/trajectory_io.hpp"

namespace edx::datasets {
namespace fs = std::filesystem;
namespace {

using Projection = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

/// calib.txt: lines "P0: 12 numbers" (3x4 row-major projection matrices of the rectified
/// cameras). Returns P0 and P1; the other keys (P2, P3, Tr) are not needed.
std::array<Projection, 2> read_projections(const fs::path& file) {
  const TextTable table(file, FieldSeparator::kWhitespace);
  std::map<std::string, Projection> projections;
  for (const auto& row : table.rows()) {
    const std::string& key = row.fields.front();
    if (key.size() < 2 || key.back() != ':') {
      table.fail(row, fmt::format("expected 'KEY: numbers', got '{}'", key));
    }
    const std::string name = key.substr(0, key.size() - 1);
    if (name != "P0" && name != "P1") continue;
    if (row.fields.size() != 13) {
      table.fail(row,
                 fmt::format("key '{}' expects 12 numbers, got {}", name, row.fields.size() - 1));
    }
    Projection P;
    for (std::size_t i = 0; i < 12; ++i) {
      P(static_cast<int>(i / 4), static_cast<int>(i % 4)) = table.real(row, i + 1, name);
    }
    projections[name] = P;
  }
  std::array<Projection, 2> result;
  for (int camera = 0; camera < 2; ++camera) {
    const std::string name = fmt::format("P{}", camera);
    const auto found = projections.find(name);
    if (found == projections.end()) {
      throw std::runtime_error(fmt::format("{}: missing key '{}'", file.string(), name));
    }
    result[static_cast<std::size_t>(camera)] = found->second;
  }
  return result;
}

/// times.txt: one time in seconds a line -> nanoseconds (rounded), strictly increasing.
std::vector<TimestampNs> read_times(const fs::path& file) {
  const TextTable table(file, FieldSeparator::kWhitespace);
  std::vector<TimestampNs> times;
  times.reserve(table.rows().size());
  for (const auto& row : table.rows()) {
    table.require_field_count(row, 1);
    const double seconds = table.real(row, 0, "time [s]");
    if (!(std::abs(seconds) < 9e9)) table.fail(row, "time out of range");
    const auto t_ns = static_cast<TimestampNs>(std::llround(seconds * 1e9));
    if (!times.empty() && t_ns <= times.back()) {
      table.fail(row, fmt::format("time {} s does not increase", row.fields[0]));
    }
    times.push_back(t_ns);
  }
  if (times.empty()) throw std::runtime_error(fmt::format("{}: no time stamps", file.string()));
  return times;
}

/// poses/NN.txt: one 3x4 row-major [R|t] a line, T_world_cam0 of the matching frame. Parsed by
/// the trajectory reader of workloads/eval (one parser for KITTI pose files); rotations are
/// then projected onto SO(3) (they are stored to ~1e-9).
std::vector<GroundTruthPose> read_poses(const fs::path& file,
                                        const std::vector<TimestampNs>& times) {
  const eval::Trajectory trajectory =
      eval::read_trajectory(file, eval::TrajectoryFormat::kKitti, {.rotation_tolerance = 1e-4});
  if (trajectory.poses.size() != times.size()) {
    throw std::runtime_error(fmt::format("{}: {} poses for {} time stamps in times.txt",
                                         file.string(), trajectory.poses.size(), times.size()));
  }
  std::vector<GroundTruthPose> poses(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    const eval::StampedPose& stamped = trajectory.poses[i];
    if (stamped.frame_index != static_cast<std::int64_t>(i)) {
      throw std::runtime_error(fmt::format("{}:{}: pose of frame {}, expected frame {}",
                                           file.string(), stamped.line, stamped.frame_index, i));
    }
    const auto rotation = nearest_rotation(stamped.pose.linear(), 1e-4);
    if (!rotation) {
      throw std::runtime_error(
          fmt::format("{}:{}: the 3x3 part is not a rotation matrix", file.string(), stamped.line));
    }
    poses[i].t_ns = times[i];
    poses[i].T_world_body.linear() = *rotation;
    poses[i].T_world_body.translation() = stamped.pose.translation();
  }
  return poses;
}

}  // namespace

KittiDataset::KittiDataset(const fs::path& path, const DatasetOptions& options) {
  if (!fs::is_directory(path)) {
    throw std::runtime_error(fmt::format("{}: dataset folder not found", path.string()));
  }
  std::string sequence = options.kitti_sequence;
  if (fs::exists(path / "calib.txt")) {
    sequence_dir_ = fs::absolute(path).lexically_normal();
    if (!sequence_dir_.has_filename()) sequence_dir_ = sequence_dir_.parent_path();
    if (!sequence.empty() && sequence != sequence_dir_.filename().string()) {
      throw std::runtime_error(
          fmt::format("{}: sequence folder does not match sequence '{}'", path.string(), sequence));
    }
    sequence = sequence_dir_.filename().string();
    poses_file_ = sequence_dir_.parent_path().parent_path() / "poses" / (sequence + ".txt");
  } else if (fs::is_directory(path / "sequences")) {
    if (sequence.empty()) {
      throw std::runtime_error(fmt::format(
          "{}: a KITTI root needs a sequence id (e.g. \"01\"), or give the sequence folder",
          path.string()));
    }
    sequence_dir_ = path / "sequences" / sequence;
    if (!fs::is_directory(sequence_dir_)) {
      throw std::runtime_error(
          fmt::format("{}: sequence folder not found", sequence_dir_.string()));
    }
    poses_file_ = path / "poses" / (sequence + ".txt");
  } else {
    throw std::runtime_error(fmt::format(
        "{}: not a KITTI odometry sequence folder (no calib.txt) nor root (no sequences/)",
        path.string()));
  }
  for (const char* camera : {"image_0", "image_1"}) {
    if (!fs::is_directory(sequence_dir_ / camera)) {
      throw std::runtime_error(
          fmt::format("{}: image folder not found", (sequence_dir_ / camera).string()));
    }
  }

  // Rectified pair with the left camera as reference: P0 = K [I | 0], P1 = K [I | -B e_x],
  // so B = -P1(0,3) / fx.
  const fs::path calib_file = sequence_dir_ / "calib.txt";
  const auto [P0, P1] = read_projections(calib_file);
  const Eigen::Matrix3d K0 = P0.leftCols<3>(), K1 = P1.leftCols<3>();
  const double tolerance = 1e-9 * std::abs(K0(0, 0));
  if (!(K0(0, 0) > 0 && K0(1, 1) > 0) || !K0.isApprox(K1, 1e-9) ||
      P0.col(3).cwiseAbs().maxCoeff() > tolerance ||
      P1.block<2, 1>(1, 3).cwiseAbs().maxCoeff() > tolerance) {
    throw std::runtime_error(
        fmt::format("{}: P0 and P1 must describe a rectified horizontal pair: P0 = K [I | 0], "
                    "P1 = K [I | (-B, 0, 0)]",
                    calib_file.string()));
  }
  CameraIntrinsics camera;
  camera.fx = K0(0, 0);
  camera.fy = K0(1, 1);
  camera.cx = K0(0, 2);
  camera.cy = K0(1, 2);
  calibration_.baseline_m = -P1(0, 3) / camera.fx;
  if (!(calibration_.baseline_m > 0)) {
    throw std::runtime_error(fmt::format("{}: P1 puts the right camera on the left (baseline {} m)",
                                         calib_file.string(), calibration_.baseline_m));
  }
  // Body = left camera: T_body_left is the identity, the right camera sits at (B, 0, 0).
  calibration_.T_body_raw_right.translation() = Eigen::Vector3d(calibration_.baseline_m, 0, 0);

  const std::vector<TimestampNs> times = read_times(sequence_dir_ / "times.txt");
  if (times.size() > 1) {
    calibration_.frame_rate_hz = static_cast<double>(times.size() - 1) /
                                 (1e-9 * static_cast<double>(times.back() - times.front()));
  }
  std::vector<ListedImage> left, right;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const std::string file = fmt::format("{:06d}.png", i);
    left.push_back({times[i], sequence_dir_ / "image_0" / file});
    right.push_back({times[i], sequence_dir_ / "image_1" / file});
  }
  frames_ = pair_stereo_images(left, right, (sequence_dir_ / "image_0").string(),
                               (sequence_dir_ / "image_1").string(), report_);
  if (frames_.empty()) {
    throw std::runtime_error(fmt::format(
        "{}: no stereo pair (no frame of times.txt has both image_0 and image_1 images)",
        sequence_dir_.string()));
  }

  // KITTI states no resolution: the first left image sets it, every other image must match.
  {
    const cv::Mat first = read_gray_image(frames_.front().left);
    image_size_ = first.size();
  }
  camera.width = image_size_.width;
  camera.height = image_size_.height;
  calibration_.raw_left = calibration_.raw_right = calibration_.rectified = camera;
  if (options.resize) {
    calibration_.rectified = scale_intrinsics(camera, *options.resize);
    output_size_ = *options.resize;
  }

  if (fs::exists(poses_file_)) {
    ground_truth_ = read_poses(poses_file_, times);
  } else {
    spdlog::info("{}: no ground truth ({} not found)", name(), poses_file_.string());
    poses_file_.clear();
  }
  load_frame(0);
  spdlog::debug("{}: {} stereo frames, {} ground-truth poses", name(), frames_.size(),
                ground_truth_.size());
}

std::string KittiDataset::name() const { return "kitti:" + sequence_dir_.string(); }

StereoFrame KittiDataset::load_frame(std::size_t index) const {
  if (index >= frames_.size()) {
    throw std::out_of_range(
        fmt::format("{}: frame {} out of range ({} frames)", name(), index, frames_.size()));
  }
  const StereoImagePair& pair = frames_[index];
  const std::string size_source = "size of " + frames_.front().left.string();
  StereoFrame frame;
  frame.index = index;
  frame.t_ns = pair.t_ns;
  frame.left = read_gray_image(pair.left, image_size_, size_source);
  frame.right = read_gray_image(pair.right, image_size_, size_source);
  if (output_size_) {
    frame.left = resize_image(frame.left, *output_size_);
    frame.right = resize_image(frame.right, *output_size_);
  }
  return frame;
}

}  // namespace edx::datasets
