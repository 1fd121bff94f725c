#pragma once
// SO(3) helpers shared by the backends: hat, exponential and logarithm maps and the right Jacobian.
//   Exp(w) = I + sin|w|/|w| [w]x + (1 - cos|w|)/|w|^2 [w]x^2       (Rodrigues)
//   Jr(w)  = I - (1 - cos|w|)/|w|^2 [w]x + (|w| - sin|w|)/|w|^3 [w]x^2
// Each backend states its own perturbation convention (VIO: left, SLAM: right).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace edx::backend {

/// [w]x, the cross-product matrix: skew(w) v = w x v.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d s;
  s << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return s;
}

/// Exp(w) = rotation by |w| about w/|w| (Rodrigues).
inline Eigen::Matrix3d so3_exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

/// Log(R), the rotation vector of R.
inline Eigen::Vector3d so3_log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// Jr(w), the right Jacobian of SO(3).
inline Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  const Eigen::Matrix3d W = skew(w);
  if (angle < 1e-6) return Eigen::Matrix3d::Identity() - 0.5 * W;
  const double a2 = angle * angle;
  return Eigen::Matrix3d::Identity() - (1 - std::cos(angle)) / a2 * W +
         (angle - std::sin(angle)) / (a2 * angle) * W * W;
}

}  // namespace edx::backend
