#pragma once
// Reader of EuRoC ASL folders (mav0/ with cam0, cam1, imu0, state_groundtruth_estimate0 and the
// edx extension gps0); the layout and each file's columns are in docs/DATASETS.md.
#include <filesystem>
#include <optional>

#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/frame_pairing.hpp"
#include "workloads/datasets/stereo_rectifier.hpp"

namespace edx::datasets {

/// An EuRoC sequence: reads every CSV and YAML file at construction, rectifies the stereo pair
/// (maps computed once) and loads images on demand.
class EurocDataset final : public Dataset {
 public:
  /// `path`: the folder holding mav0/, or mav0/ itself. Throws std::runtime_error naming the
  /// file (and line or key) on bad input.
  EurocDataset(const std::filesystem::path& path, const DatasetOptions& options);

  std::string name() const override;
  DatasetFormat format() const override { return DatasetFormat::kEuroc; }
  const StereoCalibration& calibration() const override { return calibration_; }
  std::size_t frame_count() const override { return frames_.size(); }
  TimestampNs frame_time(std::size_t index) const override { return frames_.at(index).t_ns; }
  StereoFrame load_frame(std::size_t index) const override;
  const std::vector<ImuSample>& imu() const override { return imu_; }
  std::optional<ImuNoise> imu_noise() const override { return imu_noise_; }
  const std::vector<GpsFix>& gps() const override { return gps_; }
  const std::vector<GroundTruthPose>& ground_truth() const override { return ground_truth_; }
  const LoadReport& load_report() const override { return report_; }

 private:
  std::filesystem::path mav0_;
  StereoCalibration calibration_;
  std::optional<StereoRectifier> rectifier_;
  std::optional<cv::Size> output_size_;
  std::vector<StereoImagePair> frames_;
  std::vector<ImuSample> imu_;
  std::optional<ImuNoise> imu_noise_;
  std::vector<GpsFix> gps_;
  std::vector<GroundTruthPose> ground_truth_;
  LoadReport report_;
};

}  // namespace edx::datasets
