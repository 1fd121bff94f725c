// IMU and GPS simulation: a noise-free IMU, read back from the written files and integrated from
// the true initial state, follows the written ground truth; noise and bias statistics match the
// model; GPS rate, noise and drop-outs.
#include "workloads/datasets/synthetic/inertial.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/workloads/synthetic/synthetic_test_support.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"

namespace edx::synthetic {
namespace {

namespace fs = std::filesystem;

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

struct IntegrationError {
  double position_m = 0;
  double rotation_deg = 0;
  double seconds = 0;
};

/// Integrates imu0/data.csv from the first ground-truth state (midpoint rotation, trapezoidal
/// velocity, position with the linear-acceleration term) and compares with the last one.
IntegrationError integrate_files(const fs::path& mav0) {
  const auto imu = testing::read_numeric_csv(mav0 / "imu0" / "data.csv");
  const auto gt = testing::read_ground_truth(mav0);
  EXPECT_EQ(imu.size(), gt.size());
  const Eigen::Vector3d g(0, 0, -9.81);
  Eigen::Matrix3d R = gt.front().q.toRotationMatrix();
  Eigen::Vector3d v = gt.front().v, p = gt.front().p;
  for (std::size_t k = 0; k + 1 < imu.size(); ++k) {
    const double dt = (imu[k + 1][0] - imu[k][0]) * 1e-9;
    const Eigen::Vector3d w0(imu[k][1], imu[k][2], imu[k][3]),
        w1(imu[k + 1][1], imu[k + 1][2], imu[k + 1][3]);
    const Eigen::Vector3d f0(imu[k][4], imu[k][5], imu[k][6]),
        f1(imu[k + 1][4], imu[k + 1][5], imu[k + 1][6]);
    const Eigen::Matrix3d R1 = R * exp_so3(0.5 * (w0 + w1) * dt);
    const Eigen::Vector3d a0 = R * f0 + g, a1 = R1 * f1 + g;
    p += v * dt + dt * dt / 6.0 * (2 * a0 + a1);
    v += 0.5 * (a0 + a1) * dt;
    R = R1;
  }
  IntegrationError e;
  e.position_m = (p - gt.back().p).norm();
  e.rotation_deg =
      Eigen::AngleAxisd(R.transpose() * gt.back().q.toRotationMatrix()).angle() * 180 / M_PI;
  e.seconds = (imu.back()[0] - imu.front()[0]) * 1e-9;
  return e;
}

TEST(SyntheticImu, NoiseFreeImuIntegratesToTheGroundTruth) {
  for (const Scenario scenario : {Scenario::kIndoorUnknown, Scenario::kOutdoorUnknown}) {
    SCOPED_TRACE(std::string(to_string(scenario)));
    testing::TempDir dir("imu_" + std::string(to_string(scenario)));
    GenerateOptions o;
    o.scenario = scenario;
    o.frames = 101;  // 5 s
    o.resolution = Resolution{96, 64};
    o.seed = 5;
    o.out = dir.path() / "out";
    o.imu.noise_free = true;
    o.image.enabled = false;
    generate_dataset(o);
    const IntegrationError e = integrate_files(o.out / "mav0");
    EXPECT_NEAR(e.seconds, 5.0, 1e-9);
    EXPECT_LT(e.position_m, 0.03);
    EXPECT_LT(e.rotation_deg, 0.05);
    std::printf("[ figures ] %s: noise-free IMU integrated over %.1f s: %.2e m, %.2e deg\n",
                std::string(to_string(scenario)).c_str(), e.seconds, e.position_m, e.rotation_deg);
    // The ideal IMU writes zero noise figures.
    const auto first = testing::read_numeric_csv(o.out / "mav0" / "imu0" / "data.csv").front();
    EXPECT_EQ(first.size(), 7u);
    const auto gt = testing::read_ground_truth(o.out / "mav0");
    EXPECT_EQ(gt.front().bg.norm() + gt.front().ba.norm(), 0.0);
  }
}

// Long-run consistency of the IMU with its own ground truth, turning and straight: the ideal
// samples, integrated from the true initial state by a 4th-order scheme over pairs of sample
// intervals (h = 10 ms: Simpson's rule for v and p, 4th-order Magnus for R, the middle sample at
// h/2), reproduce the written poses over 60 s. Bound: Simpson's global error is
// T h^4 max|a^(4)| / 2880 ~ 60 * 1e-8 * 10 / 2880 = 2e-9 m/s in v, ~1e-7 m in p after 60 s; the
// Magnus remainder is O(h^5 |w|^2 |w'|) per step. Any modelling error is orders above this: a
// 1 ms offset between gyro and attitude at 0.5 rad/s tilts the specific force by 5e-4 rad
// (5e-3 m/s^2, i.e. 9 m after 60 s), and a 1e-4 relative error in gravity gives 1.8 m.
TEST(SyntheticImu, IdealImuIntegratesToTheGroundTruthOverAMinute) {
  for (const bool outdoor : {false, true}) {
    SCOPED_TRACE(outdoor ? "street" : "warehouse");
    const Scene scene = outdoor ? build_street(1) : build_warehouse(1);
    const PlannedTrajectory planned = plan_trajectory(scene, 60.0, 3, {});
    ImuModel model;
    model.noise_free = true;
    const InertialTrack track = simulate_inertial(planned.trajectory, 0, 12001, model, 1);
    const auto& imu = track.imu;
    const auto& gt = track.ground_truth;
    const Eigen::Vector3d g(0, 0, -kGravity);
    Eigen::Matrix3d R = gt.front().orientation.toRotationMatrix();
    Eigen::Vector3d p = gt.front().position, v = gt.front().velocity;
    double worst_p = 0, worst_v = 0, worst_rad = 0, max_rate = 0;
    for (std::size_t k = 0; k + 2 < imu.size(); k += 2) {
      const double h = static_cast<double>(imu[k + 2].t_ns - imu[k].t_ns) * 1e-9;
      const Eigen::Vector3d &w0 = imu[k].gyro_rad_s, &wm = imu[k + 1].gyro_rad_s,
                            &w1 = imu[k + 2].gyro_rad_s;
      // 4th-order Magnus: Omega = h/6 (w0 + 4 wm + w1) + h^2/12 w0 x w1; over the first half,
      // with w(h/4) from the parabola through w0, wm, w1: (3 w0 + 6 wm - w1) / 8.
      const Eigen::Vector3d wq = (3 * w0 + 6 * wm - w1) / 8;
      const Eigen::Matrix3d Rm =
          R * exp_so3(h / 12 * (w0 + 4 * wq + wm) + h * h / 48 * w0.cross(wm));
      const Eigen::Matrix3d R1 =
          R * exp_so3(h / 6 * (w0 + 4 * wm + w1) + h * h / 12 * w0.cross(w1));
      const Eigen::Vector3d a0 = R * imu[k].accel_m_s2 + g, am = Rm * imu[k + 1].accel_m_s2 + g,
                            a1 = R1 * imu[k + 2].accel_m_s2 + g;
      p += v * h + h * h / 6 * (a0 + 2 * am);  // Simpson on v(t) = v0 + int a
      v += h / 6 * (a0 + 4 * am + a1);
      R = R1;
      worst_p = std::max(worst_p, (p - gt[k + 2].position).norm());
      worst_v = std::max(worst_v, (v - gt[k + 2].velocity).norm());
      worst_rad = std::max(
          worst_rad,
          Eigen::AngleAxisd(R.transpose() * gt[k + 2].orientation.toRotationMatrix()).angle());
      max_rate = std::max(max_rate, w1.norm());
    }
    EXPECT_GT(max_rate, 0.3);  // the run turns
    EXPECT_LT(worst_p, 2e-5);
    EXPECT_LT(worst_v, 1e-6);
    EXPECT_LT(worst_rad, 1e-8);
    std::printf(
        "[ figures ] %s: ideal IMU, 4th-order integration over 60 s (peak rate %.2f rad/s): "
        "max error %.1e m, %.1e m/s, %.1e rad\n",
        outdoor ? "street" : "warehouse", max_rate, worst_p, worst_v, worst_rad);
  }
}

TEST(SyntheticImu, NoiseAndBiasWalkMatchTheModel) {
  const Scene scene = build_warehouse(1);
  const PlannedTrajectory planned = plan_trajectory(scene, 40.0, 3, {});
  ImuModel model;                  // EuRoC densities
  const std::size_t count = 8000;  // 40 s at 200 Hz
  const InertialTrack noisy = simulate_inertial(planned.trajectory, 0, count, model, 9);
  ImuModel ideal_model = model;
  ideal_model.noise_free = true;
  const InertialTrack ideal = simulate_inertial(planned.trajectory, 0, count, ideal_model, 9);
  ASSERT_EQ(noisy.imu.size(), count);
  double gyro_sq = 0, accel_sq = 0, dbg_sq = 0, dba_sq = 0;
  for (std::size_t k = 0; k < count; ++k) {
    // measurement - truth - bias = white noise
    const Eigen::Vector3d ng =
        noisy.imu[k].gyro_rad_s - ideal.imu[k].gyro_rad_s - noisy.ground_truth[k].gyro_bias;
    const Eigen::Vector3d na =
        noisy.imu[k].accel_m_s2 - ideal.imu[k].accel_m_s2 - noisy.ground_truth[k].accel_bias;
    gyro_sq += ng.squaredNorm();
    accel_sq += na.squaredNorm();
    if (k > 0) {
      dbg_sq +=
          (noisy.ground_truth[k].gyro_bias - noisy.ground_truth[k - 1].gyro_bias).squaredNorm();
      dba_sq +=
          (noisy.ground_truth[k].accel_bias - noisy.ground_truth[k - 1].accel_bias).squaredNorm();
    }
  }
  const double n3 = 3.0 * count;
  // sigma_d = density * sqrt(rate); bias step sigma = walk / sqrt(rate).
  EXPECT_NEAR(std::sqrt(gyro_sq / n3), model.gyro_noise_density * std::sqrt(200.0),
              0.03 * model.gyro_noise_density * std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(accel_sq / n3), model.accel_noise_density * std::sqrt(200.0),
              0.03 * model.accel_noise_density * std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(dbg_sq / (n3 - 3)), model.gyro_random_walk / std::sqrt(200.0),
              0.03 * model.gyro_random_walk / std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(dba_sq / (n3 - 3)), model.accel_random_walk / std::sqrt(200.0),
              0.03 * model.accel_random_walk / std::sqrt(200.0));
  // Ground truth at the IMU times and in the IMU (body) frame.
  EXPECT_EQ(noisy.ground_truth[10].t_ns, 50'000'000);
  const BodyState s = planned.trajectory.at(0.05);
  EXPECT_LT((noisy.ground_truth[10].position - s.position).norm(), 1e-12);
  EXPECT_LT((ideal.imu[10].accel_m_s2 - specific_force(s)).norm(), 1e-12);
  // At rest and level the accelerometer reads +g upwards.
  BodyState rest;
  EXPECT_LT((specific_force(rest) - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-12);
}

TEST(SyntheticGps, RateNoiseAndDropouts) {
  const Scene scene = build_street(1);
  const PlannedTrajectory planned = plan_trajectory(scene, 600.0, 3, {});
  GpsModel model;
  model.sigma_m = 0.8;
  model.dropout_rate_per_min = 2.0;
  model.dropout_mean_s = 4.0;
  const auto fixes = simulate_gps(planned.trajectory, 1000, 600.0, model, 4);
  ASSERT_FALSE(fixes.empty());
  double sq = 0;
  int gaps = 0;
  double missing_s = 0;
  for (std::size_t i = 0; i < fixes.size(); ++i) {
    const double t = static_cast<double>(fixes[i].t_ns - 1000) * 1e-9;
    sq += (fixes[i].position_m - planned.trajectory.at(t).position).squaredNorm();
    EXPECT_EQ(fixes[i].sigma_m, 0.8);
    EXPECT_EQ((fixes[i].t_ns - 1000) % 100'000'000, 0);  // on the 10 Hz grid
    if (i > 0) {
      const auto step = fixes[i].t_ns - fixes[i - 1].t_ns;
      ASSERT_GT(step, 0);
      if (step > 100'000'000) {
        ++gaps;
        missing_s += static_cast<double>(step) * 1e-9 - 0.1;
      }
    }
  }
  EXPECT_NEAR(std::sqrt(sq / (3.0 * fixes.size())), 0.8, 0.05);
  // ~20 drop-outs expected in 10 minutes, ~4 s each.
  EXPECT_GE(gaps, 8);
  EXPECT_LE(gaps, 35);
  EXPECT_NEAR(missing_s / gaps, 4.0, 1.2);
  model.dropout_rate_per_min = 0;
  const auto all = simulate_gps(planned.trajectory, 0, 600.0, model, 4);
  EXPECT_EQ(all.size(), 6001u);
}

}  // namespace
}  // namespace edx::synthetic
