#include "workloads/backend/slam/preintegration.hpp"

#include <algorithm>
#include <stdexcept>

#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {

Preintegration::Preintegration(const Eigen::Vector3d& accel_bias, const Eigen::Vector3d& gyro_bias,
                               const ImuNoiseDensities& noise)
    : noise_(noise), accel_bias_(accel_bias), gyro_bias_(gyro_bias) {
  reset();
}

void Preintegration::reset() {
  dt_ = 0;
  alpha_.setZero();
  beta_.setZero();
  delta_R_.setIdentity();
  covariance_.setZero();
  J_alpha_ba.setZero();
  J_alpha_bg.setZero();
  J_beta_ba.setZero();
  J_beta_bg.setZero();
  J_theta_bg.setZero();
}

void Preintegration::integrate(double dt, const Eigen::Vector3d& accel,
                               const Eigen::Vector3d& gyro) {
  if (!(dt > 0)) throw std::invalid_argument("Preintegration::integrate: dt must be > 0");
  steps_.push_back({dt, accel, gyro});
  propagate(steps_.back());
}

void Preintegration::repropagate(const Eigen::Vector3d& accel_bias,
                                 const Eigen::Vector3d& gyro_bias) {
  accel_bias_ = accel_bias;
  gyro_bias_ = gyro_bias;
  reset();
  for (const Step& s : steps_) propagate(s);
}

void Preintegration::propagate(const Step& step) {
  const double dt = step.dt, dt2 = dt * dt;
  const Eigen::Vector3d a = step.accel - accel_bias_;
  const Eigen::Vector3d w = step.gyro - gyro_bias_;
  const Eigen::Matrix3d R = delta_R_;
  const Eigen::Matrix3d dR = so3_exp(w * dt);
  const Eigen::Matrix3d Jr = so3_right_jacobian(w * dt);
  const Eigen::Matrix3d Ra_x = R * skew(a);

  // Error dynamics, state [alpha, theta, beta, ba, bg] (theta: right perturbation of dR):
  //   theta' = dR^T theta - Jr dt (n_g + d bg)
  //   beta'  = beta - R [a]x dt theta - R dt (n_a + d ba)
  //   alpha' = alpha + beta dt - 1/2 R [a]x dt^2 theta - 1/2 R dt^2 (n_a + d ba)
  Eigen::Matrix<double, 15, 15> F = Eigen::Matrix<double, 15, 15>::Identity();
  F.block<3, 3>(0, 3) = -0.5 * Ra_x * dt2;
  F.block<3, 3>(0, 6) = Eigen::Matrix3d::Identity() * dt;
  F.block<3, 3>(0, 9) = -0.5 * R * dt2;
  F.block<3, 3>(3, 3) = dR.transpose();
  F.block<3, 3>(3, 12) = -Jr * dt;
  F.block<3, 3>(6, 3) = -Ra_x * dt;
  F.block<3, 3>(6, 9) = -R * dt;
  // Noise [n_a, n_g, n_ba, n_bg]; discrete variances sigma^2 / dt (white), sigma^2 dt (walk).
  Eigen::Matrix<double, 15, 12> G = Eigen::Matrix<double, 15, 12>::Zero();
  G.block<3, 3>(0, 0) = -0.5 * R * dt2;
  G.block<3, 3>(3, 3) = -Jr * dt;
  G.block<3, 3>(6, 0) = -R * dt;
  G.block<3, 3>(9, 6) = Eigen::Matrix3d::Identity();
  G.block<3, 3>(12, 9) = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 12, 1> q;
  q << Eigen::Vector3d::Constant(noise_.accel_noise * noise_.accel_noise / dt),
      Eigen::Vector3d::Constant(noise_.gyro_noise * noise_.gyro_noise / dt),
      Eigen::Vector3d::Constant(noise_.accel_walk * noise_.accel_walk * dt),
      Eigen::Vector3d::Constant(noise_.gyro_walk * noise_.gyro_walk * dt);
  covariance_ = F * covariance_ * F.transpose() + G * q.asDiagonal() * G.transpose();

  // Bias Jacobians: the blocks of F's recursion driven by the bias columns.
  J_alpha_ba += J_beta_ba * dt - 0.5 * R * dt2;
  J_alpha_bg += J_beta_bg * dt - 0.5 * Ra_x * J_theta_bg * dt2;
  J_beta_ba -= R * dt;
  J_beta_bg -= Ra_x * J_theta_bg * dt;
  J_theta_bg = dR.transpose() * J_theta_bg - Jr * dt;

  alpha_ += beta_ * dt + 0.5 * R * a * dt2;
  beta_ += R * a * dt;
  delta_R_ = R * dR;
  const Eigen::Quaterniond q_norm(delta_R_);
  delta_R_ = q_norm.normalized().toRotationMatrix();
  dt_ += dt;
}

Eigen::Vector3d Preintegration::corrected_alpha(const Eigen::Vector3d& ba,
                                                const Eigen::Vector3d& bg) const {
  return alpha_ + J_alpha_ba * (ba - accel_bias_) + J_alpha_bg * (bg - gyro_bias_);
}

Eigen::Vector3d Preintegration::corrected_beta(const Eigen::Vector3d& ba,
                                               const Eigen::Vector3d& bg) const {
  return beta_ + J_beta_ba * (ba - accel_bias_) + J_beta_bg * (bg - gyro_bias_);
}

Eigen::Matrix3d Preintegration::corrected_delta_R(const Eigen::Vector3d& bg) const {
  return delta_R_ * so3_exp(J_theta_bg * (bg - gyro_bias_));
}

void integrate_interval(Preintegration& preintegration, std::int64_t& last_t_ns,
                        datasets::ImuSample& last_sample,
                        std::span<const datasets::ImuSample> samples, std::int64_t t_ns) {
  for (const datasets::ImuSample& s : samples) {
    if (s.t_ns <= last_t_ns) continue;
    const std::int64_t until = std::min(s.t_ns, t_ns);
    if (until > last_t_ns) {
      preintegration.integrate(static_cast<double>(until - last_t_ns) * 1e-9,
                               last_sample.accel_m_s2, last_sample.gyro_rad_s);
      last_t_ns = until;
    }
    if (s.t_ns <= t_ns) last_sample = s;
  }
  if (t_ns > last_t_ns) {
    preintegration.integrate(static_cast<double>(t_ns - last_t_ns) * 1e-9, last_sample.accel_m_s2,
                             last_sample.gyro_rad_s);
    last_t_ns = t_ns;
  }
}

}  // namespace edx::backend::slam
