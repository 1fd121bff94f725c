#pragma once
// One interface for every sensor-data source (EuRoC ASL folders, KITTI odometry, the synthetic
// world written in the EuRoC layout): rectified stereo frames, IMU samples, GPS fixes, ground
// truth and calibration. The folder layouts and file formats are described in docs/DATASETS.md.
//
// Conventions
//  - Time stamps are integer nanoseconds (EuRoC's own unit); KITTI seconds are converted.
//  - Poses are Eigen::Isometry3d named T_a_b: they map coordinates of frame b into frame a,
//    p_a = T_a_b * p_b.
//  - "body" is the IMU frame where an IMU exists, else the left camera frame (KITTI).
//  - Frames are handed over rectified (row-aligned stereo, no distortion), 8-bit grayscale.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace edx::datasets {

using TimestampNs = std::int64_t;

/// Pinhole intrinsics with optional radial-tangential distortion (k1, k2, p1, p2), as in EuRoC.
struct CameraIntrinsics {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  ///< radtan: k1, k2, p1, p2 (empty: none)
};

/// Calibration of the rectified stereo pair as the frames are handed over.
struct StereoCalibration {
  CameraIntrinsics raw_left, raw_right;  ///< as stated by the dataset, before rectification
  CameraIntrinsics rectified;            ///< shared by both rectified images, no distortion
  double baseline_m = 0;                 ///< distance between the rectified optical centres
  /// Rectified left camera in the body frame (p_body = T_body_left * p_left). The rectified
  /// right camera sits at (baseline_m, 0, 0) in the rectified left frame, same orientation.
  Eigen::Isometry3d T_body_left = Eigen::Isometry3d::Identity();
  /// The dataset's own (unrectified) camera extrinsics, EuRoC's T_BS of cam0 and cam1.
  Eigen::Isometry3d T_body_raw_left = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_body_raw_right = Eigen::Isometry3d::Identity();
  double frame_rate_hz = 0;  ///< nominal camera rate (sensor.yaml rate_hz; KITTI: from times)
};

/// One rectified stereo pair.
struct StereoFrame {
  std::size_t index = 0;
  TimestampNs t_ns = 0;
  cv::Mat left, right;  ///< CV_8UC1, rectified
};

/// Gyroscope (rad/s) and accelerometer (m/s^2) reading in the body frame.
struct ImuSample {
  TimestampNs t_ns = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};

/// A GPS position fix, already expressed in the dataset's local world frame (metres).
struct GpsFix {
  TimestampNs t_ns = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double sigma_m = 0;  ///< 1-sigma horizontal/vertical noise stated by the source
};

/// Ground-truth body pose in the world frame, with velocity and IMU biases when the source has
/// them (EuRoC state_groundtruth_estimate0 has all three; KITTI only the pose).
struct GroundTruthPose {
  TimestampNs t_ns = 0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Vector3d> velocity_m_s;     ///< in the world frame
  std::optional<Eigen::Vector3d> gyro_bias_rad_s;  ///< in the body frame
  std::optional<Eigen::Vector3d> accel_bias_m_s2;  ///< in the body frame
};

/// IMU noise densities and random walks (Kalibr/EuRoC imu0/sensor.yaml), when known.
struct ImuNoise {
  double gyro_noise_density = 0;   ///< rad/s/sqrt(Hz)
  double gyro_random_walk = 0;     ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = 0;  ///< m/s^2/sqrt(Hz)
  double accel_random_walk = 0;    ///< m/s^3/sqrt(Hz)
  double rate_hz = 0;
  /// Turn-on bias, 1 sigma per axis, when the sensor file states it (edx's keys
  /// `gyroscope_bias_sigma` [rad/s] and `accelerometer_bias_sigma` [m/s^2]; EuRoC has neither).
  std::optional<double> gyro_bias_sigma;
  std::optional<double> accel_bias_sigma;
};

/// What the reader skipped while indexing the frames, so callers and tests can check it
/// without parsing logs. Each non-zero count was logged once as a spdlog warning.
struct LoadReport {
  std::size_t left_rows = 0, right_rows = 0;  ///< frame rows listed by the source
  std::size_t left_missing_images = 0;        ///< left rows whose image file does not exist
  std::size_t right_missing_images = 0;       ///< right rows whose image file does not exist
  std::size_t left_unpaired = 0;      ///< left images with no right image of the same time stamp
  std::size_t right_unpaired = 0;     ///< right images with no left image of the same time stamp
  std::vector<std::string> warnings;  ///< the warnings as logged, one line each
};

enum class DatasetFormat { kEuroc, kKitti };

/// Parses "euroc" or "kitti"; anything else throws std::runtime_error listing those.
DatasetFormat parse_dataset_format(std::string_view text);
std::string_view to_string(DatasetFormat format);

/// Parses a resolution "WxH" (e.g. "640x480"); throws std::runtime_error on anything else.
cv::Size parse_resolution(std::string_view text);

/// Options of open_dataset (plain struct; defaults give native-resolution rectified frames).
struct DatasetOptions {
  /// When set, rectified frames are resized to this size with cv::INTER_AREA and the rectified
  /// intrinsics scaled with them: fx' = fx*sx, fy' = fy*sy, cx' = (cx+0.5)*sx-0.5,
  /// cy' = (cy+0.5)*sy-0.5 with sx = W'/W, sy = H'/H (pixel-centre convention of cv::resize).
  std::optional<cv::Size> resize;
  /// Free scaling of cv::stereoRectify for EuRoC: 0 keeps only valid pixels (no black border),
  /// 1 keeps every source pixel. Ignored for KITTI (already rectified).
  double rectify_alpha = 0.0;
  /// KITTI sequence id ("01") when the path given is the dataset root holding sequences/ and
  /// poses/; leave empty when the path is the sequence folder itself.
  std::string kitti_sequence;
};

/// A sequence of stereo frames with its side streams. Images are loaded on demand;
/// load_frame is const and safe to call from several threads.
class Dataset {
 public:
  virtual ~Dataset() = default;

  /// Human-readable source, e.g. "euroc:/path/mav0" or "kitti:/path/sequences/01".
  virtual std::string name() const = 0;
  virtual DatasetFormat format() const = 0;
  virtual const StereoCalibration& calibration() const = 0;

  virtual std::size_t frame_count() const = 0;
  virtual TimestampNs frame_time(std::size_t index) const = 0;
  /// Loads and rectifies frame `index`; throws std::runtime_error naming the file on failure
  /// (unreadable image, size different from the calibration) or std::out_of_range.
  virtual StereoFrame load_frame(std::size_t index) const = 0;

  virtual const std::vector<ImuSample>& imu() const = 0;  ///< empty when no IMU
  virtual std::optional<ImuNoise> imu_noise() const = 0;
  virtual const std::vector<GpsFix>& gps() const = 0;                    ///< empty when no GPS
  virtual const std::vector<GroundTruthPose>& ground_truth() const = 0;  ///< may be empty
  virtual const LoadReport& load_report() const = 0;
};

/// Opens a dataset folder. EuRoC: the folder holding mav0/ or mav0/ itself. KITTI: a sequence
/// folder (sequences/NN, poses from ../../poses/NN.txt), or the root holding sequences/ and
/// poses/ with options.kitti_sequence set. Throws std::runtime_error naming the file (and line
/// or key) on any bad input.
std::unique_ptr<Dataset> open_dataset(const std::filesystem::path& path, DatasetFormat format,
                                      const DatasetOptions& options = {});

/// Ground-truth pose at an arbitrary time: linear interpolation of position (and velocity,
/// biases) and slerp of orientation between the two bracketing samples. Returns std::nullopt
/// when t_ns lies outside the samples or the bracketing samples are more than max_gap_ns apart.
/// `ground_truth` must be sorted by strictly increasing time (as every Dataset hands it over).
std::optional<GroundTruthPose> interpolate_ground_truth(
    const std::vector<GroundTruthPose>& ground_truth, TimestampNs t_ns,
    TimestampNs max_gap_ns = std::numeric_limits<TimestampNs>::max());

}  // namespace edx::datasets
