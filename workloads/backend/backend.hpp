#pragma once
// The interface every localization backend implements (paper Sec. IV-A: registration, VIO,
// SLAM), and what it is handed per frame. A backend consumes the stereo frontend's features plus
// the side streams that arrived since the previous frame, estimates the body pose, and reports
// every kernel it ran with its measured host time, sizes and, inside the accelerable kernels,
// the matrix primitives (KernelRecorder, docs/TRACE.md kernels and ops tables).
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "workloads/datasets/dataset.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend {

/// Rectified stereo geometry at the processed resolution, and the camera's mounting.
struct BackendCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< rectified pinhole intrinsics, px
  double baseline_m = 0;                  ///< right camera at (baseline_m, 0, 0) in the left frame
  /// Rectified left camera in the body frame (p_body = T_body_left * p_left); the body is the
  /// IMU frame where there is an IMU, else the left camera (identity).
  Eigen::Isometry3d T_body_left = Eigen::Isometry3d::Identity();

  /// The camera of a dataset's calibration (rectified intrinsics after any resize).
  static BackendCamera from(const datasets::StereoCalibration& calibration);
};

/// Everything a backend receives for one stereo frame.
struct BackendInput {
  std::int64_t t_ns = 0;                              ///< the frame's time stamp
  const frontend::FrontendFrame* frontend = nullptr;  ///< features of this frame (never null)
  /// The rectified left image the frontend processed (8-bit grey), for a backend that looks at
  /// image windows on the host (the VIO's first-window check); may be null.
  const cv::Mat* left_image = nullptr;
  /// IMU samples with t_prev < t_ns' <= t_ns (t_prev: the previous frame's time; on the first
  /// frame, every sample up to t_ns). Empty for data without an IMU.
  std::span<const datasets::ImuSample> imu;
  /// GPS fixes with t_prev < t <= t_ns. Empty when there is no fix (indoors, outages).
  std::span<const datasets::GpsFix> gps;
};

/// What a backend returns for one frame.
struct BackendOutput {
  /// The body pose in the backend's world frame; empty while initializing or after a failure.
  std::optional<Eigen::Isometry3d> T_world_body;
  std::string status = "ok";                 ///< "ok", "initializing", or why the frame failed
  std::vector<trace::KernelRecord> kernels;  ///< in execution order (KernelRecorder::take())
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual trace::BackendMode mode() const = 0;
  /// Processes the next frame. Frames come in increasing time. Throws std::runtime_error only
  /// for misuse (e.g. a missing frontend frame); estimation failures go into `status`.
  virtual BackendOutput process(const BackendInput& input) = 0;
};

}  // namespace edx::backend
