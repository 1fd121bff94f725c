#pragma once
// Ground-truth-free initialization of the filter from the first frames.
//
// Static (accelerometer SD and mean track motion below thresholds): the mean specific force is
// -g in the body frame, so R_WI maps it onto +z (yaw set to 0), the gyro bias is the mean gyro
// reading, v = 0.
// Moving: camera poses of frames k relative to frame 0 by chaining frame-to-frame PnP (RANSAC):
// frame k against the points frame k-1 triangulated by stereo, T_CkC0 = T_CkCk-1 T_Ck-1C0; the
// gyro bias b from their rotations (VINS-Mono's gyroscope bias calibration): the gyro-integrated
// R_0k(b) = R_0k(0) Exp(D_k b) fitted to the visual R_0k by least squares; rotations R_0k
// (I0 <- Ik) by integrating the gyro less b; the
// accelerometer preintegrated in I0, alpha_k = double integral of R_0(t) a(t), beta_k = its single
// integral; then velocity v0 and gravity g0 in I0 from the linear least squares
//   p_k = v0 t_k + g0 t_k^2 / 2 + alpha_k,
// g0 rescaled to |g| and v0 solved again; R_W0 maps g0 onto (0, 0, -|g|).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "workloads/backend/vio/feature_track.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::backend::vio {

/// A feature of one frame for the initializer.
struct FrameFeature {
  std::int64_t id = 0;
  Observation observation;
  double depth_m = 0;  ///< stereo depth in the left camera (0: none)
};

struct InitialState {
  std::int64_t t_ns = 0;  ///< time of the last gathered frame: the state's time
  Eigen::Matrix3d R_WI = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  bool static_start = false;
};

class Initializer {
 public:
  /// focal_px turns the pixel thresholds into normalized units.
  Initializer(const VioOptions& options, const Eigen::Isometry3d& T_body_left, double focal_px);

  /// Adds one frame (its IMU samples since the previous one and its features). Returns the
  /// initial state once the frames suffice; std::nullopt while gathering or when the motion
  /// does not determine the state yet (the oldest frame is then dropped and gathering goes on).
  std::optional<InitialState> add_frame(std::int64_t t_ns, std::span<const datasets::ImuSample> imu,
                                        std::vector<FrameFeature> features);
  const std::string& last_reason() const { return reason_; }

 private:
  struct Frame {
    std::int64_t t_ns = 0;
    std::vector<FrameFeature> features;
  };
  std::optional<InitialState> try_static();
  std::optional<InitialState> try_moving();
  /// Body poses T_I0_Ik of frames k relative to frame 0 by chaining frame-to-frame PnP, frame k
  /// against the stereo points of frame k-1: T_CkC0 = T_CkCk-1 T_Ck-1C0, T_I0_Ik = T_IC T_C0Ck
  /// T_IC^-1. std::nullopt (and the reason) when a step has too few points or inliers.
  std::optional<std::vector<Eigen::Isometry3d>> chained_pnp_poses();

  VioOptions options_;
  Eigen::Isometry3d T_body_left_;
  double focal_px_;
  std::vector<Frame> frames_;
  std::vector<datasets::ImuSample> imu_;
  std::string reason_;
};

}  // namespace edx::backend::vio
