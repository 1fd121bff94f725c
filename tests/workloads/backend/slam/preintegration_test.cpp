// IMU preintegration against closed-form motion, and its bias Jacobians against re-integration.
#include "workloads/backend/slam/preintegration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {
namespace {

const ImuNoiseDensities kNoise{1.7e-4, 2e-3, 1.9e-5, 3e-3};

TEST(Preintegration, ConstantAccelerationWithoutRotation) {
  // a = (1, -2, 0.5) m/s^2 for 0.5 s in 100 steps: beta = a t, alpha = a t^2 / 2, dR = I.
  Preintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kNoise);
  const Eigen::Vector3d a(1, -2, 0.5);
  for (int i = 0; i < 100; ++i) pre.integrate(0.005, a, Eigen::Vector3d::Zero());
  EXPECT_NEAR(pre.dt(), 0.5, 1e-12);
  EXPECT_TRUE(pre.beta().isApprox(a * 0.5, 1e-12));
  EXPECT_TRUE(pre.alpha().isApprox(a * 0.125, 1e-12));
  EXPECT_TRUE(pre.delta_R().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(Preintegration, ConstantRateRotation) {
  // w = 0.4 rad/s about z for 1 s: dR = Rz(0.4).
  Preintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kNoise);
  for (int i = 0; i < 200; ++i) pre.integrate(0.005, Eigen::Vector3d::Zero(), {0, 0, 0.4});
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).matrix();
  EXPECT_TRUE(pre.delta_R().isApprox(expected, 1e-9));
  // Variance of theta_z over T = 1 s: gyro white noise, sigma^2 / dt * dt^2 per step = sigma^2 T,
  // plus the integrated gyro bias random walk, sigma_w^2 T^3 / 3.
  EXPECT_NEAR(pre.covariance()(5, 5),
              kNoise.gyro_noise * kNoise.gyro_noise + kNoise.gyro_walk * kNoise.gyro_walk / 3.0,
              2e-12);
}

TEST(Preintegration, BiasJacobiansMatchReintegration) {
  Preintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kNoise);
  for (int i = 0; i < 60; ++i) {
    const double t = i * 0.005;
    pre.integrate(0.005, {0.3 * std::sin(3 * t), 9.81 + 0.2 * t, -0.5},
                  {0.2, -0.5 * std::cos(2 * t), 0.8});
  }
  const Eigen::Vector3d dba(0.02, -0.01, 0.015), dbg(0.003, 0.002, -0.004);
  Preintegration moved = pre;
  moved.repropagate(dba, dbg);
  // First-order prediction vs exact re-integration: errors of second order in the bias change.
  EXPECT_LT((pre.corrected_alpha(dba, dbg) - moved.alpha()).norm(), 1e-6);
  EXPECT_LT((pre.corrected_beta(dba, dbg) - moved.beta()).norm(), 1e-5);
  EXPECT_LT(so3_log(pre.corrected_delta_R(dbg).transpose() * moved.delta_R()).norm(), 1e-6);
  // And the correction is not trivially zero.
  EXPECT_GT((pre.alpha() - moved.alpha()).norm(), 1e-4);
  EXPECT_GT(so3_log(pre.delta_R().transpose() * moved.delta_R()).norm(), 1e-4);
}

TEST(Preintegration, IntervalsHoldEachReadingUntilTheNextSample) {
  Preintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), kNoise);
  datasets::ImuSample first;
  first.t_ns = 0;
  first.accel_m_s2 = {1, 0, 0};
  std::vector<datasets::ImuSample> samples(2);
  samples[0].t_ns = 10'000'000;
  samples[0].accel_m_s2 = {2, 0, 0};
  samples[1].t_ns = 30'000'000;
  samples[1].accel_m_s2 = {5, 0, 0};
  std::int64_t t = 0;
  integrate_interval(pre, t, first, samples, 20'000'000);
  // 10 ms at 1 m/s^2 then 10 ms at 2 m/s^2; the sample at 30 ms is not reached yet.
  EXPECT_EQ(t, 20'000'000);
  EXPECT_NEAR(pre.beta().x(), 0.01 * 1 + 0.01 * 2, 1e-12);
  EXPECT_EQ(first.accel_m_s2.x(), 2);
}

}  // namespace
}  // namespace edx::backend::slam
