#pragma once
// The IMU noise model both inertial backends use (VIO's propagator, SLAM's preintegration):
// continuous-time white-noise densities and bias random walks in Kalibr units. Over a step of
// dt seconds a density sigma gives a reading the variance sigma^2 / dt (its integral sigma^2 dt)
// and a random walk sigma_w the bias the variance sigma_w^2 dt; each backend states its own
// discretization.
#include "workloads/datasets/dataset.hpp"

namespace edx::backend {

/// Continuous-time IMU noise (densities and random walks, Kalibr units).
struct ImuNoiseDensities {
  double gyro_noise = 0;   ///< rad/s/sqrt(Hz)
  double accel_noise = 0;  ///< m/s^2/sqrt(Hz)
  double gyro_walk = 0;    ///< rad/s^2/sqrt(Hz)
  double accel_walk = 0;   ///< m/s^3/sqrt(Hz)

  /// A dataset's sensor noise, every density and walk multiplied by `scale` (the VIO's
  /// imu_noise_scale; 1 leaves the values exactly as they are).
  static ImuNoiseDensities from(const datasets::ImuNoise& noise, double scale = 1.0) {
    return {noise.gyro_noise_density * scale, noise.accel_noise_density * scale,
            noise.gyro_random_walk * scale, noise.accel_random_walk * scale};
  }
};

}  // namespace edx::backend
