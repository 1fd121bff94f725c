#pragma once
// The EKF update of the paper's Eq. 1, shared by the MSCKF feature update and GPS fusion:
//   S = H P H^T + R,   S K^T = H P  (K = P H^T S^-1),
// S factored by Cholesky, S = L L^T (potrf), then forward substitution L Y = H P and back
// substitution L^T K^T = Y (trsm), and K = (K^T)^T (transpose). Then
//   dx = K r,   P <- P - K (H P),   P <- (P + P^T)/2.
// Both are offloadable kernels: they compute at the workload's precision (trace::Precision), as
// the backend units would: operands rounded to it on the way in, every operation in it, results
// widened back to the host's double (exactly) on the way out.
#include <Eigen/Core>

#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/vio_state.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend::vio {

struct KalmanGain {
  Eigen::MatrixXd K;    ///< n x m
  Eigen::MatrixXd PHt;  ///< P H^T, n x m
  bool ok = false;      ///< false when S was not positive definite
};

/// K of Eq. 1 for measurement noise R = diag(noise_var), computed at `precision`. When `ops` is
/// given, each matrix primitive is recorded on it (a kernel must be open).
KalmanGain kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H,
                       const Eigen::VectorXd& noise_var, KernelRecorder* ops,
                       trace::Precision precision = trace::Precision::kFp64);

/// P <- P - K (P H^T)^T, kept symmetric. Returns false (and leaves P unchanged) when a diagonal
/// entry would turn negative. When `ops` is given, its primitives are recorded on it: the gemm
/// P - K (P H^T)^T (n x n of m, a symmetric result) and the symmetrization (P + P^T) / 2 on the
/// transpose unit (n x n). Computed at `precision`.
bool update_covariance(Eigen::MatrixXd& P, const KalmanGain& gain, KernelRecorder* ops,
                       trace::Precision precision = trace::Precision::kFp64);

/// update_covariance on the state's P (its primitives recorded on `ops` when given), then dx = K r
/// applied to the state. Returns false (and leaves the state unchanged) when the covariance update
/// fails.
bool apply_update(VioState& state, const KalmanGain& gain, const Eigen::VectorXd& r,
                  KernelRecorder* ops, trace::Precision precision = trace::Precision::kFp64);

}  // namespace edx::backend::vio
