#pragma once
// Smooth 6-DoF trajectories with analytically known derivatives.
//
// Position is a uniform cubic B-spline (C2: continuous acceleration, so the simulated
// accelerometer is continuous); its control points are samples of a route through the scene's
// free corridors, timed by an acceleration-limited speed profile. Attitude is
// R_world_body = Rz(yaw) Ry(pitch) Rx(roll) with yaw following the horizontal velocity plus a
// smooth wobble and small pitch/roll wobbles, all with closed-form rates, so the body angular
// velocity (the ideal gyroscope reading) is exact.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "workloads/datasets/synthetic/scenes.hpp"

namespace edx::synthetic {

/// Uniform cubic B-spline p(t) = sum_{k=0..3} B_k(u) P_{i+k}, i = floor((t - t0) / dt),
/// u = (t - t0) / dt - i, with
///   B0 = (1-u)^3/6, B1 = (3u^3 - 6u^2 + 4)/6, B2 = (-3u^3 + 3u^2 + 3u + 1)/6, B3 = u^3/6;
/// velocity and acceleration use dB/du / dt and d2B/du2 / dt^2.
class CubicBSpline {
 public:
  /// Needs at least 4 control points; defined on [t0, t0 + (n - 3) dt].
  CubicBSpline(std::vector<Eigen::Vector3d> control_points, double t0, double dt);

  double t_begin() const { return t0_; }
  double t_end() const { return t0_ + static_cast<double>(points_.size() - 3) * dt_; }

  struct Sample {
    Eigen::Vector3d position, velocity, acceleration;
  };
  /// Evaluates at t (clamped to [t_begin, t_end]).
  Sample evaluate(double t) const;

 private:
  std::vector<Eigen::Vector3d> points_;
  double t0_, dt_;
};

/// Sum of sinusoids w(t) = sum a_k sin(omega_k t + phi_k), with w'(t) in closed form.
struct Wobble {
  std::array<double, 3> amplitude{}, omega{}, phase{};
  double value(double t) const;
  double rate(double t) const;
};

/// Full kinematic state of the body (IMU) frame at time t.
struct BodyState {
  double t = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< world, m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< world, m/s
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< world, m/s^2
  Eigen::Matrix3d R_world_body = Eigen::Matrix3d::Identity();
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();  ///< body angular velocity, rad/s

  Eigen::Isometry3d T_world_body() const;
};

class Trajectory {
 public:
  /// Trajectory time t maps to spline time t + time_offset.
  Trajectory(CubicBSpline spline, double time_offset, Wobble yaw, Wobble pitch, Wobble roll);

  /// State at trajectory time t (seconds since the start of the sequence).
  BodyState at(double t) const;
  /// Longest t at which the trajectory is defined.
  double duration() const { return spline_.t_end() - time_offset_; }

 private:
  CubicBSpline spline_;
  double time_offset_;
  Wobble yaw_, pitch_, roll_;
};

/// Euler ZYX (yaw, pitch, roll) rates to body angular velocity:
///   omega_b = [roll' - yaw' sin(pitch),
///              pitch' cos(roll) + yaw' cos(pitch) sin(roll),
///              -pitch' sin(roll) + yaw' cos(pitch) cos(roll)].
Eigen::Vector3d euler_zyx_rates_to_body(double pitch, double roll, double yaw_rate,
                                        double pitch_rate, double roll_rate);

struct PlannedTrajectory {
  Trajectory trajectory;
  std::vector<int> route;  ///< lane-graph nodes visited, in order
  int attempts = 1;        ///< routes tried until one kept its clearance
};

/// How a later run through the same world relates to an earlier run's route.
enum class RevisitMode {
  /// Re-traverse the earlier route from its start in the same direction (a localization run
  /// through mapped space), lane offset by lateral_offset_m and cruise/turn speeds scaled by
  /// speed_scale; height and wobbles are drawn afresh.
  kRetraverse,
  /// Start at the node one third along the earlier route and leave it in a direction the
  /// earlier run did not take there (no viewpoint of the earlier run is passed again).
  kDiverge,
};

struct Revisit {
  std::vector<int> route;  ///< lane-graph nodes of the earlier run (at least 2)
  RevisitMode mode = RevisitMode::kRetraverse;
  double lateral_offset_m = 0.3;  ///< kRetraverse: extra offset right of the earlier lane
  double speed_scale = 0.85;      ///< kRetraverse: factor on the cruise and turn speeds
};

/// Plans a trajectory of at least `duration_s` through the scene from seed `seed`.
/// `body_points` are points rigidly attached to the body (e.g. camera centres) that must keep
/// the scene's clearance along with the body origin. When `revisit` is given the route follows
/// or leaves an earlier run's route (RevisitMode). Throws std::runtime_error when no
/// collision-free route is found or the revisit options are out of range.
PlannedTrajectory plan_trajectory(const Scene& scene, double duration_s, std::uint64_t seed,
                                  const std::vector<Eigen::Vector3d>& body_points,
                                  const Revisit* revisit = nullptr);

}  // namespace edx::synthetic
