#include "workloads/datasets/euroc_dataset.hpp"

#include <fmt/core.h>
#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

#include "workloads/datasets/image_io.hpp"
#include "workloads/datasets/rotation_check.hpp"
#include "workloads/datasets/text_table.hpp"

namespace edx::datasets {
namespace fs = std::filesystem;
namespace {

/// A YAML file of key: value pairs (EuRoC sensor.yaml); failures name the file and the key.
class YamlFile {
 public:
  explicit YamlFile(fs::path file) : file_(std::move(file)) {
    if (!fs::is_regular_file(file_)) {
      throw std::runtime_error(fmt::format("{}: file not found", file_.string()));
    }
    try {
      root_ = YAML::LoadFile(file_.string());
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(fmt::format("{}: not valid YAML: {}", file_.string(), e.what()));
    }
    if (!root_.IsMap()) {
      throw std::runtime_error(fmt::format("{}: expected a YAML mapping of keys", file_.string()));
    }
  }

  [[noreturn]] void fail(std::string_view key, std::string_view message) const {
    throw std::runtime_error(fmt::format("{}: key '{}': {}", file_.string(), key, message));
  }

  bool has(std::string_view key) const { return root_[std::string(key)].IsDefined(); }

  YAML::Node node(std::string_view key) const {
    const YAML::Node node = root_[std::string(key)];
    if (!node.IsDefined() || node.IsNull()) {
      throw std::runtime_error(fmt::format("{}: missing key '{}'", file_.string(), key));
    }
    return node;
  }

  std::string text(std::string_view key) const {
    const YAML::Node value = node(key);
    if (!value.IsScalar()) fail(key, "expected a single value");
    return value.Scalar();
  }

  double number(std::string_view key) const {
    double value = 0;
    if (!parse_real(text(key), value)) fail(key, "expected a number");
    return value;
  }

  /// A list of exactly `count` numbers, e.g. intrinsics: [fu, fv, cu, cv].
  std::vector<double> numbers(std::string_view key, std::size_t count) const {
    return numbers_of(node(key), key, count);
  }

  /// A 4x4 rigid transform stored as {rows: 4, cols: 4, data: [16 numbers, row-major]}.
  Eigen::Isometry3d transform(std::string_view key) const {
    const YAML::Node value = node(key);
    if (!value.IsMap()) fail(key, "expected a matrix {rows: 4, cols: 4, data: [16 numbers]}");
    for (const char* dimension : {"rows", "cols"}) {
      std::int64_t size = 0;
      if (!value[dimension].IsScalar() || !parse_integer(value[dimension].Scalar(), size) ||
          size != 4) {
        fail(key, fmt::format("'{}' must be 4", dimension));
      }
    }
    if (!value["data"].IsDefined()) fail(key, "missing 'data'");
    const std::vector<double> data = numbers_of(value["data"], key, 16);
    Eigen::Matrix4d matrix;
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) matrix(r, c) = data[static_cast<std::size_t>(4 * r + c)];
    }
    if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
      fail(key, "last row must be [0, 0, 0, 1]");
    }
    const auto rotation = nearest_rotation(matrix.topLeftCorner<3, 3>(), 1e-6);
    if (!rotation) fail(key, "top-left 3x3 block is not a rotation matrix");
    Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
    transform.linear() = *rotation;
    transform.translation() = matrix.topRightCorner<3, 1>();
    return transform;
  }

 private:
  std::vector<double> numbers_of(const YAML::Node& list, std::string_view key,
                                 std::size_t count) const {
    const std::string expected = fmt::format("expected a list of {} numbers", count);
    if (!list.IsSequence() || list.size() != count) fail(key, expected);
    std::vector<double> values(count);
    for (std::size_t i = 0; i < count; ++i) {
      if (!list[i].IsScalar() || !parse_real(list[i].Scalar(), values[i])) fail(key, expected);
    }
    return values;
  }

  fs::path file_;
  YAML::Node root_;
};

/// One camera's sensor.yaml: pinhole intrinsics, radial-tangential distortion, T_BS, rate.
struct EurocCamera {
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_body_camera = Eigen::Isometry3d::Identity();
  double rate_hz = 0;
};

EurocCamera read_camera(const fs::path& yaml_file) {
  const YamlFile yaml(yaml_file);
  if (yaml.has("camera_model") && yaml.text("camera_model") != "pinhole") {
    yaml.fail("camera_model",
              fmt::format("'{}' is not supported (expected pinhole)", yaml.text("camera_model")));
  }
  EurocCamera camera;
  const auto resolution = yaml.numbers("resolution", 2);
  for (const double value : resolution) {
    if (!(value >= 1 && value <= 65536 && value == std::floor(value))) {
      yaml.fail("resolution", "expected [width, height] in whole pixels");
    }
  }
  camera.intrinsics.width = static_cast<int>(resolution[0]);
  camera.intrinsics.height = static_cast<int>(resolution[1]);
  const auto intrinsics = yaml.numbers("intrinsics", 4);
  if (!(intrinsics[0] > 0 && intrinsics[1] > 0)) {
    yaml.fail("intrinsics", "expected [fu, fv, cu, cv] with fu, fv > 0");
  }
  camera.intrinsics.fx = intrinsics[0];
  camera.intrinsics.fy = intrinsics[1];
  camera.intrinsics.cx = intrinsics[2];
  camera.intrinsics.cy = intrinsics[3];
  const std::string model = yaml.text("distortion_model");
  if (model != "radial-tangential" && model != "radtan") {
    yaml.fail("distortion_model",
              fmt::format("'{}' is not supported (expected radial-tangential)", model));
  }
  camera.intrinsics.distortion = yaml.numbers("distortion_coefficients", 4);
  camera.rate_hz = yaml.number("rate_hz");
  if (!(camera.rate_hz > 0)) yaml.fail("rate_hz", "expected a positive rate");
  camera.T_body_camera = yaml.transform("T_BS");
  return camera;
}

/// Fails unless time stamps strictly increase down the file.
void require_increasing(const TextTable& table, const TableRow& row, TimestampNs t_ns,
                        std::optional<TimestampNs> previous) {
  if (previous && t_ns <= *previous) {
    table.fail(row, fmt::format("time stamp {} does not increase (previous: {})", t_ns, *previous));
  }
}

/// cam?/data.csv: "#timestamp [ns],filename"; images in cam?/data/.
std::vector<ListedImage> read_image_list(const fs::path& camera_dir) {
  const TextTable table(camera_dir / "data.csv", FieldSeparator::kComma);
  std::vector<ListedImage> images;
  images.reserve(table.rows().size());
  for (const auto& row : table.rows()) {
    table.require_field_count(row, 2);
    const TimestampNs t_ns = table.integer(row, 0, "timestamp [ns]");
    require_increasing(table, row, t_ns,
                       images.empty() ? std::nullopt : std::optional(images.back().t_ns));
    if (row.fields[1].empty()) table.fail(row, "field 2 (filename) is empty");
    images.push_back({t_ns, camera_dir / "data" / row.fields[1]});
  }
  return images;
}

/// imu0/data.csv: timestamp [ns], w_RS_S (3, rad/s), a_RS_S (3, m/s^2).
std::vector<ImuSample> read_imu(const fs::path& file) {
  const TextTable table(file, FieldSeparator::kComma);
  std::vector<ImuSample> samples;
  samples.reserve(table.rows().size());
  for (const auto& row : table.rows()) {
    table.require_field_count(row, 7);
    ImuSample sample;
    sample.t_ns = table.integer(row, 0, "timestamp [ns]");
    require_increasing(table, row, sample.t_ns,
                       samples.empty() ? std::nullopt : std::optional(samples.back().t_ns));
    sample.gyro_rad_s = {table.real(row, 1, "w_x"), table.real(row, 2, "w_y"),
                         table.real(row, 3, "w_z")};
    sample.accel_m_s2 = {table.real(row, 4, "a_x"), table.real(row, 5, "a_y"),
                         table.real(row, 6, "a_z")};
    samples.push_back(sample);
  }
  return samples;
}

/// imu0/sensor.yaml: Kalibr noise model; the IMU must be the body frame (T_BS = identity).
ImuNoise read_imu_noise(const fs::path& yaml_file) {
  const YamlFile yaml(yaml_file);
  ImuNoise noise;
  const auto non_negative = [&](const char* key) {
    const double value = yaml.number(key);
    if (!(value >= 0)) yaml.fail(key, "expected a non-negative number");
    return value;
  };
  noise.gyro_noise_density = non_negative("gyroscope_noise_density");
  noise.gyro_random_walk = non_negative("gyroscope_random_walk");
  noise.accel_noise_density = non_negative("accelerometer_noise_density");
  noise.accel_random_walk = non_negative("accelerometer_random_walk");
  noise.rate_hz = yaml.number("rate_hz");
  if (!(noise.rate_hz > 0)) yaml.fail("rate_hz", "expected a positive rate");
  const auto optional_positive = [&](const char* key) -> std::optional<double> {
    if (!yaml.has(key)) return std::nullopt;
    const double value = yaml.number(key);
    if (!(value > 0)) yaml.fail(key, "expected a positive number");
    return value;
  };
  noise.gyro_bias_sigma = optional_positive("gyroscope_bias_sigma");
  noise.accel_bias_sigma = optional_positive("accelerometer_bias_sigma");
  if (yaml.has("T_BS") && !yaml.transform("T_BS").isApprox(Eigen::Isometry3d::Identity(), 1e-9)) {
    yaml.fail("T_BS", "the IMU must be the body frame (identity), as in EuRoC");
  }
  return noise;
}

/// state_groundtruth_estimate0/data.csv: timestamp, p (3), q_wxyz (4), v (3), b_w (3), b_a (3).
std::vector<GroundTruthPose> read_ground_truth(const fs::path& file) {
  const TextTable table(file, FieldSeparator::kComma);
  std::vector<GroundTruthPose> poses;
  poses.reserve(table.rows().size());
  for (const auto& row : table.rows()) {
    table.require_field_count(row, 17);
    GroundTruthPose pose;
    pose.t_ns = table.integer(row, 0, "timestamp [ns]");
    require_increasing(table, row, pose.t_ns,
                       poses.empty() ? std::nullopt : std::optional(poses.back().t_ns));
    const auto vector_at = [&](std::size_t column, const char* what) {
      return Eigen::Vector3d(table.real(row, column, what), table.real(row, column + 1, what),
                             table.real(row, column + 2, what));
    };
    Eigen::Quaterniond q(table.real(row, 4, "q_w"), table.real(row, 5, "q_x"),
                         table.real(row, 6, "q_y"), table.real(row, 7, "q_z"));
    if (std::abs(q.norm() - 1) > 1e-3) {
      table.fail(row, fmt::format("quaternion (fields 5-8) has norm {}, expected 1", q.norm()));
    }
    pose.T_world_body.linear() = q.normalized().toRotationMatrix();
    pose.T_world_body.translation() = vector_at(1, "p");
    pose.velocity_m_s = vector_at(8, "v");
    pose.gyro_bias_rad_s = vector_at(11, "b_w");
    pose.accel_bias_m_s2 = vector_at(14, "b_a");
    poses.push_back(pose);
  }
  return poses;
}

/// gps0/data.csv (edx extension): timestamp [ns], p_x, p_y, p_z [m] in the ground-truth world
/// frame, sigma [m].
std::vector<GpsFix> read_gps(const fs::path& file) {
  const TextTable table(file, FieldSeparator::kComma);
  std::vector<GpsFix> fixes;
  fixes.reserve(table.rows().size());
  for (const auto& row : table.rows()) {
    table.require_field_count(row, 5);
    GpsFix fix;
    fix.t_ns = table.integer(row, 0, "timestamp [ns]");
    require_increasing(table, row, fix.t_ns,
                       fixes.empty() ? std::nullopt : std::optional(fixes.back().t_ns));
    fix.position_m = {table.real(row, 1, "p_x"), table.real(row, 2, "p_y"),
                      table.real(row, 3, "p_z")};
    fix.sigma_m = table.real(row, 4, "sigma");
    if (!(fix.sigma_m > 0)) table.fail(row, "field 5 (sigma) must be positive");
    fixes.push_back(fix);
  }
  return fixes;
}

fs::path find_mav0(const fs::path& path) {
  if (!fs::is_directory(path)) {
    throw std::runtime_error(fmt::format("{}: dataset folder not found", path.string()));
  }
  if (fs::is_directory(path / "mav0")) return path / "mav0";
  if (fs::is_directory(path / "cam0")) return path;
  throw std::runtime_error(
      fmt::format("{}: not an EuRoC ASL folder (no mav0/ folder, no cam0/ folder)", path.string()));
}

}  // namespace

EurocDataset::EurocDataset(const fs::path& path, const DatasetOptions& options)
    : mav0_(find_mav0(path)) {
  for (const char* camera : {"cam0", "cam1"}) {
    if (!fs::is_directory(mav0_ / camera)) {
      throw std::runtime_error(
          fmt::format("{}: camera folder not found (EuRoC ASL layout)", (mav0_ / camera).string()));
    }
  }
  const fs::path left_yaml = mav0_ / "cam0" / "sensor.yaml";
  const fs::path right_yaml = mav0_ / "cam1" / "sensor.yaml";
  const EurocCamera left = read_camera(left_yaml);
  const EurocCamera right = read_camera(right_yaml);
  calibration_.raw_left = left.intrinsics;
  calibration_.raw_right = right.intrinsics;
  calibration_.T_body_raw_left = left.T_body_camera;
  calibration_.T_body_raw_right = right.T_body_camera;
  calibration_.frame_rate_hz = left.rate_hz;

  if (!(options.rectify_alpha == -1 ||
        (options.rectify_alpha >= 0 && options.rectify_alpha <= 1))) {
    throw std::runtime_error(
        fmt::format("rectify_alpha {} is not valid (expected -1 or a value within [0, 1])",
                    options.rectify_alpha));
  }
  // p_right = T_right_left * p_left with T_right_left = T_BS1^-1 * T_BS0.
  const Eigen::Isometry3d T_right_left = right.T_body_camera.inverse() * left.T_body_camera;
  try {
    rectifier_.emplace(left.intrinsics, right.intrinsics, T_right_left, options.rectify_alpha);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        fmt::format("{} and {}: {}", left_yaml.string(), right_yaml.string(), e.what()));
  }
  calibration_.rectified = rectifier_->rectified();
  calibration_.baseline_m = rectifier_->baseline_m();
  // p_rect_left = R1 * p_raw_left, so T_body_left = T_BS0 * [R1^T | 0].
  Eigen::Isometry3d T_raw_left_rect = Eigen::Isometry3d::Identity();
  T_raw_left_rect.linear() = rectifier_->R_rect_left().transpose();
  calibration_.T_body_left = left.T_body_camera * T_raw_left_rect;
  if (options.resize) {
    calibration_.rectified = scale_intrinsics(calibration_.rectified, *options.resize);
    output_size_ = *options.resize;
  }

  const fs::path left_csv = mav0_ / "cam0" / "data.csv";
  const fs::path right_csv = mav0_ / "cam1" / "data.csv";
  frames_ = pair_stereo_images(read_image_list(mav0_ / "cam0"), read_image_list(mav0_ / "cam1"),
                               left_csv.string(), right_csv.string(), report_);
  if (frames_.empty()) {
    throw std::runtime_error(fmt::format(
        "{}: no stereo pair (no time stamp has both a cam0 and a cam1 image)", mav0_.string()));
  }

  if (fs::is_directory(mav0_ / "imu0")) {
    imu_ = read_imu(mav0_ / "imu0" / "data.csv");
    if (fs::exists(mav0_ / "imu0" / "sensor.yaml")) {
      imu_noise_ = read_imu_noise(mav0_ / "imu0" / "sensor.yaml");
    }
  }
  if (fs::is_directory(mav0_ / "state_groundtruth_estimate0")) {
    ground_truth_ = read_ground_truth(mav0_ / "state_groundtruth_estimate0" / "data.csv");
  }
  if (fs::is_directory(mav0_ / "gps0")) gps_ = read_gps(mav0_ / "gps0" / "data.csv");

  // Fail early on an unreadable or wrongly sized first pair rather than mid-run.
  load_frame(0);
  spdlog::debug("{}: {} stereo frames, {} IMU samples, {} ground-truth poses, {} GPS fixes", name(),
                frames_.size(), imu_.size(), ground_truth_.size(), gps_.size());
}

std::string EurocDataset::name() const { return "euroc:" + mav0_.string(); }

StereoFrame EurocDataset::load_frame(std::size_t index) const {
  if (index >= frames_.size()) {
    throw std::out_of_range(
        fmt::format("{}: frame {} out of range ({} frames)", name(), index, frames_.size()));
  }
  const StereoImagePair& pair = frames_[index];
  const cv::Size left_size(calibration_.raw_left.width, calibration_.raw_left.height);
  const cv::Size right_size(calibration_.raw_right.width, calibration_.raw_right.height);
  const cv::Mat left = read_gray_image(
      pair.left, left_size, "resolution in " + (mav0_ / "cam0" / "sensor.yaml").string());
  const cv::Mat right = read_gray_image(
      pair.right, right_size, "resolution in " + (mav0_ / "cam1" / "sensor.yaml").string());
  StereoFrame frame;
  frame.index = index;
  frame.t_ns = pair.t_ns;
  frame.left = rectifier_->rectify_left(left);
  frame.right = rectifier_->rectify_right(right);
  if (output_size_) {
    frame.left = resize_image(frame.left, *output_size_);
    frame.right = resize_image(frame.right, *output_size_);
  }
  return frame;
}

}  // namespace edx::datasets
