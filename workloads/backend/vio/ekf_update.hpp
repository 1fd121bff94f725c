#pragma once
// The EKF update of the paper's Eq. 1, shared by the MSCKF feature update and GPS fusion:
//   S = H P H^T + R,   S K^T = H P  (K = P H^T S^-1),
// S factored by Cholesky, S = L L^T (potrf), then forward substitution L Y = H P and back
// substitution L^T K^T = Y (trsm), and K = (K^T)^T (transpose). Then
//   dx = K r,   P <- P - K (H P),   P <- (P + P^T)/2.
#include <Eigen/Core>

#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/vio_state.hpp"

namespace edx::backend::vio {

struct KalmanGain {
  Eigen::MatrixXd K;    ///< n x m
  Eigen::MatrixXd PHt;  ///< P H^T, n x m
  bool ok = false;      ///< false when S was not positive definite
};

/// K of Eq. 1 for measurement noise R = diag(noise_var). When `ops` is given, each matrix
/// primitive is recorded on it (a kernel must be open).
KalmanGain kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H,
                       const Eigen::VectorXd& noise_var, KernelRecorder* ops);

/// P <- P - K (P H^T)^T, kept symmetric. Returns false (and leaves P unchanged) when a diagonal
/// entry would turn negative. When `ops` is given, its primitives are recorded on it: the gemm
/// P - K (P H^T)^T (n x n of m, a symmetric result) and the symmetrization (P + P^T) / 2 on the
/// transpose unit (n x n).
bool update_covariance(Eigen::MatrixXd& P, const KalmanGain& gain, KernelRecorder* ops);

/// update_covariance on the state's P (its primitives recorded on `ops` when given), then dx = K r
/// applied to the state. Returns false (and leaves the state unchanged) when the covariance update
/// fails.
bool apply_update(VioState& state, const KalmanGain& gain, const Eigen::VectorXd& r,
                  KernelRecorder* ops);

}  // namespace edx::backend::vio
