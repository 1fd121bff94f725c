#pragma once
// IMU preintegration between two keyframes i and j (Forster et al., "On-Manifold
// Preintegration", as used by VINS-Fusion), in the body frame of keyframe i and independent of
// the keyframe states. With bias-corrected readings w = w~ - bg0, a = a~ - ba0 held over each
// step dt (zero-order hold):
//   alpha <- alpha + beta dt + 1/2 dR a dt^2      (position delta)
//   beta  <- beta + dR a dt                       (velocity delta)
//   dR    <- dR Exp(w dt)                         (rotation delta)
// The 15x15 covariance of [d alpha, d theta, d beta, d ba, d bg] is propagated with the error
// dynamics F and noise G of that step, and the bias Jacobians with the same recursion, so that
// a bias change (dba, dbg) is applied to first order without re-integrating:
//   alpha(b) ~ alpha + J_alpha_ba dba + J_alpha_bg dbg,  dR(b) ~ dR Exp(J_theta_bg dbg), ...
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "workloads/backend/imu_noise.hpp"
#include "workloads/datasets/dataset.hpp"

namespace edx::backend::slam {

class Preintegration {
 public:
  Preintegration(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias,
                 const ImuNoiseDensities& noise);

  /// Integrates a reading held constant for dt seconds (dt > 0).
  void integrate(double dt, const Eigen::Vector3d& accel, const Eigen::Vector3d& gyro);
  /// Integrates all readings again with new linearization biases.
  void repropagate(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias);

  double dt() const { return dt_; }
  const Eigen::Vector3d& alpha() const { return alpha_; }
  const Eigen::Vector3d& beta() const { return beta_; }
  const Eigen::Matrix3d& delta_R() const { return delta_R_; }
  const Eigen::Matrix<double, 15, 15>& covariance() const { return covariance_; }
  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  std::size_t steps() const { return steps_.size(); }

  // Bias Jacobians of the deltas.
  Eigen::Matrix3d J_alpha_ba = Eigen::Matrix3d::Zero(), J_alpha_bg = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_beta_ba = Eigen::Matrix3d::Zero(), J_beta_bg = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d J_theta_bg = Eigen::Matrix3d::Zero();

  /// Deltas corrected to first order for biases (ba, bg) instead of the linearization ones.
  Eigen::Vector3d corrected_alpha(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) const;
  Eigen::Vector3d corrected_beta(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) const;
  Eigen::Matrix3d corrected_delta_R(const Eigen::Vector3d& bg) const;

 private:
  struct Step {
    double dt;
    Eigen::Vector3d accel, gyro;
  };
  void reset();
  void propagate(const Step& step);

  ImuNoiseDensities noise_;
  Eigen::Vector3d accel_bias_, gyro_bias_;
  std::vector<Step> steps_;
  double dt_ = 0;
  Eigen::Vector3d alpha_, beta_;
  Eigen::Matrix3d delta_R_;
  Eigen::Matrix<double, 15, 15> covariance_;
};

/// Feeds the IMU samples of one frame interval (t_prev, t_ns] into `preintegration`, holding
/// each reading until the next sample and the last one until t_ns. `last_t_ns` is the time
/// integrated up to so far (updated); `last_sample` the reading in force at that time.
void integrate_interval(Preintegration& preintegration, std::int64_t& last_t_ns,
                        datasets::ImuSample& last_sample,
                        std::span<const datasets::ImuSample> samples, std::int64_t t_ns);

}  // namespace edx::backend::slam
