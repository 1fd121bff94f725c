#pragma once
// IMU, GPS and ground truth sampled from a trajectory.
//
// IMU (body frame = IMU frame), at t_k = k / rate:
//   gyro_k  = omega_b(t_k) + b_g,k + n_g,k
//   accel_k = R_wb(t_k)^T (a_w(t_k) - g_w) + b_a,k + n_a,k,    g_w = (0, 0, -9.81)
// with discrete white noise n ~ N(0, sigma^2 * rate) (sigma the noise density) and biases
// following a random walk b_{k+1} = b_k + sigma_rw * sqrt(1 / rate) * N(0, 1), starting from
// a random initial bias. GPS fixes: body position + N(0, sigma^2) per axis, at `rate_hz`, with
// drop-outs that start at a given rate (Poisson) and last a random duration.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "workloads/datasets/dataset.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"

namespace edx::synthetic {

inline constexpr double kGravity = 9.81;

/// IMU noise model, in the Kalibr/EuRoC units of imu0/sensor.yaml; defaults are the EuRoC
/// ADIS16448 values.
struct ImuModel {
  double rate_hz = 200.0;
  double gyro_noise_density = 1.6968e-4;   ///< rad/s/sqrt(Hz)
  double gyro_random_walk = 1.9393e-5;     ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;     ///< m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;       ///< m/s^3/sqrt(Hz)
  double initial_gyro_bias_sigma = 2e-3;   ///< rad/s, per axis
  double initial_accel_bias_sigma = 2e-2;  ///< m/s^2, per axis
  bool noise_free = false;                 ///< ideal IMU: no noise, zero biases (for tests)
};

struct GpsModel {
  double rate_hz = 10.0;
  double sigma_m = 0.5;               ///< per-axis standard deviation
  double dropout_rate_per_min = 1.0;  ///< expected drop-out starts per minute
  double dropout_mean_s = 3.0;        ///< mean drop-out duration (uniform in [0.5, 1.5] x mean)
};

/// Ground truth at one instant, EuRoC state_groundtruth_estimate0 columns.
struct GroundTruthState {
  datasets::TimestampNs t_ns = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< q_world_body
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
};

struct InertialTrack {
  std::vector<datasets::ImuSample> imu;
  std::vector<GroundTruthState> ground_truth;  ///< at the IMU time stamps, with true biases
};

/// Samples IMU and ground truth at t0_ns + k * period for k = 0..count-1; trajectory time of
/// sample k is k * period (seconds). The period must be a whole number of nanoseconds.
InertialTrack simulate_inertial(const Trajectory& trajectory, datasets::TimestampNs t0_ns,
                                std::size_t count, const ImuModel& model, std::uint64_t seed);

/// GPS fixes every 1/rate over [0, duration_s] (trajectory time), stamped t0_ns + t.
std::vector<datasets::GpsFix> simulate_gps(const Trajectory& trajectory,
                                           datasets::TimestampNs t0_ns, double duration_s,
                                           const GpsModel& model, std::uint64_t seed);

/// Ideal accelerometer reading (specific force) of a body state: R_wb^T (a_w - g_w).
Eigen::Vector3d specific_force(const BodyState& state);

}  // namespace edx::synthetic
