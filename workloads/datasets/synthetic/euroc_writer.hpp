#pragma once
// Writes one sequence in the EuRoC ASL folder layout (as read by the EuRoC reader):
//   mav0/body.yaml
//   mav0/cam0|cam1/{data.csv, sensor.yaml, data/<t_ns>.png}
//   mav0/imu0/{data.csv, sensor.yaml}
//   mav0/state_groundtruth_estimate0/{data.csv, sensor.yaml}
//   mav0/gps0/{data.csv, sensor.yaml}            (only when GPS is written)
// with the column headers and the %YAML:1.0 sensor files of the real dataset. Camera sensor
// files state the rectified pinhole intrinsics with zero radial-tangential distortion; T_BS of
// cam1 is T_BS of cam0 moved one baseline along the camera x axis. Numbers are printed with a
// fixed format, so files are byte-identical for identical inputs.
#include <filesystem>
#include <string>
#include <vector>

#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/synthetic/inertial.hpp"
#include "workloads/datasets/synthetic/rig.hpp"

namespace edx::synthetic {

class EurocWriter {
 public:
  /// Creates `mav0` and its sensor folders. `comment` goes into body.yaml.
  EurocWriter(std::filesystem::path mav0, const StereoRig& rig, double camera_rate_hz,
              std::string comment);

  /// Writes the two PNGs of one frame at once and remembers the time stamp for data.csv.
  void add_frame(datasets::TimestampNs t_ns, const cv::Mat& left, const cv::Mat& right);
  void write_imu(const std::vector<datasets::ImuSample>& samples, const ImuModel& model);
  void write_ground_truth(const std::vector<GroundTruthState>& states);
  void write_gps(const std::vector<datasets::GpsFix>& fixes, const GpsModel& model);
  /// Writes the camera lists and all sensor.yaml files.
  void finish();

  const std::filesystem::path& mav0() const { return mav0_; }

 private:
  std::filesystem::path mav0_;
  StereoRig rig_;
  double camera_rate_hz_;
  std::string comment_;
  std::vector<datasets::TimestampNs> frames_;
};

/// Writes `text` to `path`; throws std::runtime_error naming the file on failure.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace edx::synthetic
