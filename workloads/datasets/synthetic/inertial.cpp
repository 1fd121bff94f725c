#include "workloads/datasets/synthetic/inertial.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "workloads/datasets/synthetic/random.hpp"

namespace edx::synthetic {

namespace {

Eigen::Vector3d normal3(Rng& rng) { return {normal(rng), normal(rng), normal(rng)}; }

std::int64_t period_ns(double rate_hz, const char* what) {
  if (!(rate_hz > 0)) throw std::runtime_error(std::string(what) + " rate must be positive");
  const double period = 1e9 / rate_hz;
  const auto ns = static_cast<std::int64_t>(std::llround(period));
  if (std::abs(period - static_cast<double>(ns)) > 1e-6) {
    throw std::runtime_error(std::string(what) + " rate " + std::to_string(rate_hz) +
                             " Hz does not give a whole number of nanoseconds");
  }
  return ns;
}

}  // namespace

Eigen::Vector3d specific_force(const BodyState& state) {
  const Eigen::Vector3d g_world(0, 0, -kGravity);
  return state.R_world_body.transpose() * (state.acceleration - g_world);
}

InertialTrack simulate_inertial(const Trajectory& trajectory, datasets::TimestampNs t0_ns,
                                std::size_t count, const ImuModel& model, std::uint64_t seed) {
  const std::int64_t step_ns = period_ns(model.rate_hz, "IMU");
  const double dt = static_cast<double>(step_ns) * 1e-9;
  Rng rng(derive_seed(seed, "imu"));
  InertialTrack track;
  track.imu.reserve(count);
  track.ground_truth.reserve(count);
  Eigen::Vector3d bg = Eigen::Vector3d::Zero(), ba = Eigen::Vector3d::Zero();
  if (!model.noise_free) {
    bg = model.initial_gyro_bias_sigma * normal3(rng);
    ba = model.initial_accel_bias_sigma * normal3(rng);
  }
  // Discrete white noise: sigma_d = density * sqrt(rate); bias step: walk * sqrt(dt).
  const double gyro_sigma = model.gyro_noise_density / std::sqrt(dt);
  const double accel_sigma = model.accel_noise_density / std::sqrt(dt);
  const double gyro_walk = model.gyro_random_walk * std::sqrt(dt);
  const double accel_walk = model.accel_random_walk * std::sqrt(dt);
  for (std::size_t k = 0; k < count; ++k) {
    const std::int64_t offset_ns = static_cast<std::int64_t>(k) * step_ns;
    const BodyState s = trajectory.at(static_cast<double>(offset_ns) * 1e-9);
    datasets::ImuSample sample;
    sample.t_ns = t0_ns + offset_ns;
    sample.gyro_rad_s = s.omega_body + bg;
    sample.accel_m_s2 = specific_force(s) + ba;
    if (!model.noise_free) {
      sample.gyro_rad_s += gyro_sigma * normal3(rng);
      sample.accel_m_s2 += accel_sigma * normal3(rng);
    }
    track.imu.push_back(sample);
    GroundTruthState gt;
    gt.t_ns = sample.t_ns;
    gt.position = s.position;
    gt.orientation = Eigen::Quaterniond(s.R_world_body).normalized();
    if (gt.orientation.w() < 0) gt.orientation.coeffs() *= -1.0;  // canonical sign
    gt.velocity = s.velocity;
    gt.gyro_bias = bg;
    gt.accel_bias = ba;
    track.ground_truth.push_back(gt);
    if (!model.noise_free) {
      bg += gyro_walk * normal3(rng);
      ba += accel_walk * normal3(rng);
    }
  }
  return track;
}

std::vector<datasets::GpsFix> simulate_gps(const Trajectory& trajectory,
                                           datasets::TimestampNs t0_ns, double duration_s,
                                           const GpsModel& model, std::uint64_t seed) {
  const std::int64_t step_ns = period_ns(model.rate_hz, "GPS");
  const double dt = static_cast<double>(step_ns) * 1e-9;
  if (model.sigma_m < 0 || model.dropout_rate_per_min < 0 || model.dropout_mean_s < 0) {
    throw std::runtime_error("GPS noise and drop-out parameters must not be negative");
  }
  Rng rng(derive_seed(seed, "gps"));
  std::vector<datasets::GpsFix> fixes;
  const double start_probability = model.dropout_rate_per_min / 60.0 * dt;
  double dropout_until = -1.0;
  for (std::int64_t k = 0;; ++k) {
    const std::int64_t offset_ns = k * step_ns;
    const double t = static_cast<double>(offset_ns) * 1e-9;
    if (t > duration_s + 1e-9) break;
    // Draw every random number for every fix so drop-outs do not shift the noise stream.
    const Eigen::Vector3d noise = model.sigma_m * normal3(rng);
    const double u_start = uniform(rng, 0, 1);
    const double u_length = uniform(rng, 0.5, 1.5);
    if (t < dropout_until) continue;
    if (u_start < start_probability) {
      dropout_until = t + u_length * model.dropout_mean_s;
      continue;
    }
    datasets::GpsFix fix;
    fix.t_ns = t0_ns + offset_ns;
    fix.position_m = trajectory.at(t).position + noise;
    fix.sigma_m = model.sigma_m;
    fixes.push_back(fix);
  }
  return fixes;
}

}  // namespace edx::synthetic
