#pragma once
// The MSCKF state: IMU pose, velocity and biases, the camera-IMU extrinsics, and a sliding
// window of stochastic clones of the IMU pose, with the covariance of its error state.
//
// Error state (left, world-frame perturbation of rotations: R = Exp(dtheta) R_hat):
//   [ dtheta_WI, dp_WI, dv_WI, db_g, db_a | dtheta_IC, dp_IC | dyaw_GV, dt_GV |
//     0          3      6      9     12     15         18       21       22
//     (dtheta_WIj, dp_WIj) per clone ]
//     25 + 6j
// (yaw_GV, t_GV): the GPS frame relative to the filter's world frame, p_G = Rz(yaw) p_W + t,
// estimated once GPS fixes are aligned (gps_fusion.hpp); unused (zero covariance) before.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "workloads/backend/so3.hpp"

namespace edx::backend::vio {

inline constexpr int kTheta = 0, kPos = 3, kVel = 6, kGyroBias = 9, kAccelBias = 12;
inline constexpr int kExtTheta = 15, kExtPos = 18;
inline constexpr int kGpsYaw = 21, kGpsPos = 22;
inline constexpr int kCoreDim = 25;  ///< error-state size without clones
inline constexpr int kImuDim = 15;   ///< the block propagated by the IMU
inline constexpr int kCloneDim = 6;

/// A stochastic clone: the IMU pose at an image time.
struct Clone {
  std::int64_t t_ns = 0;
  Eigen::Matrix3d R_WI = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  /// First estimate of p_WI (at cloning, before any update): the linearization point of the
  /// clone's dtheta Jacobian (first-estimate Jacobians, see msckf_updater.hpp). Unset: p_WI.
  Eigen::Vector3d p_fe = Eigen::Vector3d::Zero();
  bool has_fe = false;
  Eigen::Vector3d p_lin() const { return has_fe ? p_fe : p_WI; }
};

struct VioState {
  std::int64_t t_ns = 0;  ///< time of the IMU state
  Eigen::Matrix3d R_WI = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_IC = Eigen::Matrix3d::Identity();  ///< left camera in the IMU frame
  Eigen::Vector3d p_IC = Eigen::Vector3d::Zero();
  double yaw_GV = 0;  ///< GPS frame <- filter world frame
  Eigen::Vector3d t_GV = Eigen::Vector3d::Zero();
  std::vector<Clone> clones;  ///< oldest first
  /// First estimates (FEJ, Huang, Mourikis & Roumeliotis 2010): position and velocity as last
  /// propagated, before the updates of that image; the next propagation's Jacobian starts from
  /// them. Unset: the current estimate.
  Eigen::Vector3d p_fe = Eigen::Vector3d::Zero(), v_fe = Eigen::Vector3d::Zero();
  bool has_fe = false;
  /// yaw_GV when the GPS frame was aligned: the linearization point of the GPS Jacobians.
  std::optional<double> yaw_GV_fe;
  Eigen::MatrixXd P;  ///< error-state covariance, dim() x dim()

  int dim() const { return kCoreDim + kCloneDim * static_cast<int>(clones.size()); }
  static int clone_index(std::size_t clone) {
    return kCoreDim + kCloneDim * static_cast<int>(clone);
  }
  /// Index of the clone taken at t_ns, or -1.
  int find_clone(std::int64_t t_ns) const;

  /// Stochastic cloning: appends the current IMU pose as a clone; the covariance grows by
  /// P <- [P, P J^T; J P, J P J^T], J selecting (dtheta_WI, dp_WI).
  void augment_clone();
  /// Removes clone `index` (its rows and columns of P: marginalization of a Gaussian).
  void marginalize_clone(std::size_t index);
  /// Applies an error-state correction dx (size dim()).
  void correct(const Eigen::VectorXd& dx);
  /// P <- (P + P^T) / 2.
  void symmetrize();
  Eigen::Isometry3d T_world_body() const;
  Eigen::Vector3d p_lin() const { return has_fe ? p_fe : p_WI; }
  Eigen::Vector3d v_lin() const { return has_fe ? v_fe : v_WI; }
};

}  // namespace edx::backend::vio
