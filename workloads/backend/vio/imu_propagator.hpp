#pragma once
// Error-state propagation of the MSCKF at IMU rate (mean and covariance).
//
// Mean, per sample interval dt with midpoint readings w = (w_k + w_k+1)/2 - b_g,
// a = (a_k + a_k+1)/2 - b_a:
//   R+ = R Exp(w dt),  a_W = (R + R+)/2 a + g,  p+ = p + v dt + a_W dt^2/2,  v+ = v + a_W dt.
// Error state (left perturbation), one step Phi = I + ... with A = [R a]x:
//   dtheta+ = dtheta - R dt db_g
//   dp+     = dp + dt dv - A dt^2/2 dtheta - R dt^2/2 db_a
//   dv+     = dv - A dt dtheta - R dt db_a
// Discrete noise Qd: dtheta sg^2 dt, dv sa^2 dt, dp sa^2 dt^3/3 (dp dv: sa^2 dt^2/2),
// db_g sbg^2 dt, db_a sba^2 dt (Kalibr densities). The 15x15 IMU block is propagated as
// P_II <- Phi P_II Phi^T + Q, and its cross terms with the rest as P_IR <- Phi P_IR, with Phi and Q
// accumulated over all samples of the frame interval.
#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "workloads/backend/imu_noise.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/vio_state.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::backend::vio {

/// The IMU interval to an image time: each sample interval's transition Φ_k and discrete noise
/// Q_k, and the first-estimate blocks of the whole interval's Φ (integrate), from which the
/// covariance is propagated (propagate_covariance).
struct ImuInterval {
  using Mat15 = Eigen::Matrix<double, kImuDim, kImuDim>;
  bool propagated = false;  ///< false: nothing to propagate (no samples, or no time passed)
  std::vector<Mat15> Phi, Q;
  Eigen::Matrix3d Phi_v_theta = Eigen::Matrix3d::Zero();  ///< -[v1 - v0_fe - g T]x
  Eigen::Matrix3d Phi_p_theta = Eigen::Matrix3d::Zero();  ///< -[p1 - p0_fe - v0_fe T - g T²/2]x
  int steps() const { return static_cast<int>(Phi.size()); }
};

class ImuPropagator {
 public:
  ImuPropagator(const ImuNoiseDensities& noise, double gravity_m_s2);

  /// Feeds samples (increasing time); the ones up to t_ns are consumed by propagate().
  void add(std::span<const datasets::ImuSample> samples);
  /// Integrates the mean from state.t_ns to t_ns (kernel "imu_propagation") and returns the
  /// interval's transitions for the covariance.
  ImuInterval integrate(VioState& state, std::int64_t t_ns);
  /// P_II <- Φ P_II Φᵀ + Q and P_IR <- Φ P_IR with Φ = Π Φ_k (its first-estimate blocks) and
  /// Q accumulated over the interval (kernel "covariance_propagation"). With `recorder` (its
  /// kernel open) the matrix ops are described on it (docs/TRACE.md).
  void propagate_covariance(VioState& state, const ImuInterval& interval,
                            KernelRecorder* recorder = nullptr);
  /// Both. Returns the number of sample intervals integrated.
  int propagate(VioState& state, std::int64_t t_ns);
  const Eigen::Vector3d& gravity() const { return gravity_; }

 private:
  ImuNoiseDensities noise_;
  Eigen::Vector3d gravity_;
  std::vector<datasets::ImuSample> buffer_;
};

}  // namespace edx::backend::vio
