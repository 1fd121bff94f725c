#include "workloads/backend/vio/vio_state.hpp"

#include <stdexcept>

namespace edx::backend::vio {

int VioState::find_clone(std::int64_t t) const {
  for (std::size_t i = 0; i < clones.size(); ++i)
    if (clones[i].t_ns == t) return static_cast<int>(i);
  return -1;
}

void VioState::augment_clone() {
  const int n = dim();
  Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(n + kCloneDim, n + kCloneDim);
  grown.topLeftCorner(n, n) = P;
  // J P: the rows of (dtheta_WI, dp_WI), which sit at 0..5 of the error state.
  grown.block(n, 0, kCloneDim, n) = P.topRows(kCloneDim);
  grown.block(0, n, n, kCloneDim) = P.leftCols(kCloneDim);
  grown.block(n, n, kCloneDim, kCloneDim) = P.topLeftCorner(kCloneDim, kCloneDim);
  P = std::move(grown);
  clones.push_back({t_ns, R_WI, p_WI, p_lin(), true});
}

void VioState::marginalize_clone(std::size_t index) {
  if (index >= clones.size()) throw std::logic_error("vio: marginalizing a missing clone");
  const int n = dim();
  const int at = clone_index(index);
  const int tail = n - at - kCloneDim;
  Eigen::MatrixXd kept(n - kCloneDim, n - kCloneDim);
  kept.topLeftCorner(at, at) = P.topLeftCorner(at, at);
  kept.topRightCorner(at, tail) = P.topRightCorner(at, tail);
  kept.bottomLeftCorner(tail, at) = P.bottomLeftCorner(tail, at);
  kept.bottomRightCorner(tail, tail) = P.bottomRightCorner(tail, tail);
  P = std::move(kept);
  clones.erase(clones.begin() + static_cast<std::ptrdiff_t>(index));
}

void VioState::correct(const Eigen::VectorXd& dx) {
  R_WI = so3_exp(dx.segment<3>(kTheta)) * R_WI;
  p_WI += dx.segment<3>(kPos);
  v_WI += dx.segment<3>(kVel);
  gyro_bias += dx.segment<3>(kGyroBias);
  accel_bias += dx.segment<3>(kAccelBias);
  R_IC = so3_exp(dx.segment<3>(kExtTheta)) * R_IC;
  p_IC += dx.segment<3>(kExtPos);
  yaw_GV += dx(kGpsYaw);
  t_GV += dx.segment<3>(kGpsPos);
  for (std::size_t i = 0; i < clones.size(); ++i) {
    const int at = clone_index(i);
    clones[i].R_WI = so3_exp(dx.segment<3>(at)) * clones[i].R_WI;
    clones[i].p_WI += dx.segment<3>(at + 3);
  }
  // Keep the rotations orthonormal after many small updates.
  const auto orthonormalize = [](Eigen::Matrix3d& R) {
    R = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  };
  orthonormalize(R_WI);
  orthonormalize(R_IC);
  for (Clone& c : clones) orthonormalize(c.R_WI);
}

void VioState::symmetrize() { P = 0.5 * (P + P.transpose()).eval(); }

Eigen::Isometry3d VioState::T_world_body() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_WI;
  T.translation() = p_WI;
  return T;
}

}  // namespace edx::backend::vio
