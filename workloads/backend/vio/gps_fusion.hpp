#pragma once
// Loosely coupled GPS fusion (paper Sec. IV-A "Fusion"): GPS positions corrected into the
// filter through an EKF update with the antenna lever arm.
//
// The filter runs in its own gravity-aligned world frame W (yaw and origin fixed at
// initialization). The GPS frame G is related to it by a yaw about z and a translation,
// p_G = Rz(yaw_GV) p_W + t_GV, which the state carries (vio_state.hpp). Fixes are first gathered
// with the filter's antenna position at their time; once they spread over
// gps_align_min_extent_m, the least-squares 4-DoF transform (eval::align_positions, posyaw)
// initializes (yaw_GV, t_GV) with covariance s_yaw^2 = sigma^2 / sum_i |e_i,xy|^2 (e_i the centred
// fixes) and s_t^2 = sigma^2 / n per axis, correlated with the pose (gps_fusion.cpp). From then
// on each fix z (at t_fix <= t) is fused:
//   a = p_WI + R_WI l - v_WI (t - t_fix)       (antenna in W, l the lever arm in the body)
//   z = Rz(yaw) a + t + n,  n ~ N(0, sigma^2 I3)
//   H_theta = -Rz [R_WI l]x,  H_p = Rz,  H_v = -(t - t_fix) Rz,  H_yaw = [e_z]x Rz a,  H_t = I,
// chi-square gated (rows x, y of G only when gps_fuse_vertical is off). The estimate stays in
// W: GPS corrects the drift of the pose while the frame transform absorbs the (unobservable to
// VIO) choice of yaw and origin.
#include <Eigen/Geometry>
#include <span>
#include <vector>

#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/backend/vio/vio_state.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::backend::vio {

struct GpsReport {
  int fixes = 0;     ///< fixes handed in
  int fused = 0;     ///< fused into the state
  int rejected = 0;  ///< rejected by the chi-square gate
  bool aligned_now = false;
};

class GpsFusion {
 public:
  explicit GpsFusion(const VioOptions& options);

  /// Processes the fixes of one frame (state at its time); records the gps_fusion kernel when
  /// there are fixes.
  GpsReport process(VioState& state, std::span<const datasets::GpsFix> fixes,
                    KernelRecorder& recorder);
  bool aligned() const { return aligned_; }

 private:
  void align(VioState& state);

  VioOptions options_;
  bool aligned_ = false;
  std::vector<Eigen::Vector3d> filter_positions_, fix_positions_;
  std::vector<double> fix_sigmas_;
  int consecutive_rejections_ = 0;
};

}  // namespace edx::backend::vio
