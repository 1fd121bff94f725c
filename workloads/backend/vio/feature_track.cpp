#include "workloads/backend/vio/feature_track.hpp"

namespace edx::backend::vio {

void project_stereo(const Eigen::Vector3d& p_C, double baseline_m, bool stereo, Eigen::VectorXd& z,
                    Eigen::MatrixXd& dz_dpC) {
  const double X = p_C.x(), Y = p_C.y(), Z = p_C.z();
  const double iz = 1.0 / Z, iz2 = iz * iz;
  const int rows = stereo ? 3 : 2;
  z.resize(rows);
  dz_dpC.resize(rows, 3);
  z(0) = X * iz;
  z(1) = Y * iz;
  dz_dpC.row(0) << iz, 0, -X * iz2;
  dz_dpC.row(1) << 0, iz, -Y * iz2;
  if (stereo) {
    z(2) = (X - baseline_m) * iz;
    dz_dpC.row(2) << iz, 0, -(X - baseline_m) * iz2;
  }
}

Eigen::VectorXd measured(const Observation& obs) {
  Eigen::VectorXd z(obs.rows());
  z(0) = obs.left.x();
  z(1) = obs.left.y();
  if (obs.stereo) z(2) = obs.right_x;
  return z;
}

}  // namespace edx::backend::vio
