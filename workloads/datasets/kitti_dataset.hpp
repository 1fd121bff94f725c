#pragma once
// Reader of the KITTI odometry layout: sequences/NN/{image_0, image_1, calib.txt, times.txt}
// and poses/NN.txt; see docs/DATASETS.md.
#include <filesystem>
#include <optional>

#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/frame_pairing.hpp"

namespace edx::datasets {

/// A KITTI odometry sequence. Images are already rectified; body = left camera (cam0), so the
/// ground truth is the left-camera pose and T_body_left is the identity. No IMU, no GPS.
class KittiDataset final : public Dataset {
 public:
  /// `path`: the sequence folder (…/sequences/NN; poses read from …/poses/NN.txt when present),
  /// or the dataset root holding sequences/ with options.kitti_sequence = "NN".
  KittiDataset(const std::filesystem::path& path, const DatasetOptions& options);

  std::string name() const override;
  DatasetFormat format() const override { return DatasetFormat::kKitti; }
  const StereoCalibration& calibration() const override { return calibration_; }
  std::size_t frame_count() const override { return frames_.size(); }
  TimestampNs frame_time(std::size_t index) const override { return frames_.at(index).t_ns; }
  StereoFrame load_frame(std::size_t index) const override;
  const std::vector<ImuSample>& imu() const override { return no_imu_; }
  std::optional<ImuNoise> imu_noise() const override { return std::nullopt; }
  const std::vector<GpsFix>& gps() const override { return no_gps_; }
  const std::vector<GroundTruthPose>& ground_truth() const override { return ground_truth_; }
  const LoadReport& load_report() const override { return report_; }

  /// The sequence folder and the ground-truth file (empty path when there is none).
  const std::filesystem::path& sequence_dir() const { return sequence_dir_; }
  const std::filesystem::path& poses_file() const { return poses_file_; }

 private:
  std::filesystem::path sequence_dir_, poses_file_;
  StereoCalibration calibration_;
  cv::Size image_size_;
  std::optional<cv::Size> output_size_;
  std::vector<StereoImagePair> frames_;
  std::vector<GroundTruthPose> ground_truth_;
  std::vector<ImuSample> no_imu_;
  std::vector<GpsFix> no_gps_;
  LoadReport report_;
};

}  // namespace edx::datasets
