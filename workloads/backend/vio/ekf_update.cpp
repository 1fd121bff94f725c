#include "workloads/backend/vio/ekf_update.hpp"

#include <Eigen/Cholesky>

namespace edx::backend::vio {
namespace {

/// Runs fn, recording it as `op` when a recorder is given.
template <class Fn>
auto maybe_op(KernelRecorder* ops, trace::Op op, std::int64_t m, std::int64_t n, std::int64_t k,
              std::uint32_t flags, Fn&& fn) {
  if (ops) return ops->op(op, m, n, k, flags, std::forward<Fn>(fn));
  return fn();
}

}  // namespace

KalmanGain kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H,
                       const Eigen::VectorXd& noise_var, KernelRecorder* ops) {
  namespace f = trace::op_flags;
  const std::int64_t m = H.rows(), n = H.cols();
  KalmanGain gain;
  // P H^T (n x m), then S = H (P H^T) + R (m x m, symmetric).
  gain.PHt = maybe_op(ops, trace::Op::Gemm, n, m, n, f::kSymmetric | f::kTransposeB,
                      [&] { return Eigen::MatrixXd(P * H.transpose()); });
  Eigen::MatrixXd S = maybe_op(ops, trace::Op::Gemm, m, m, n, f::kSymmetric,
                               [&] { return Eigen::MatrixXd(H * gain.PHt); });
  S.diagonal() += noise_var;
  // S = L L^T.
  const Eigen::LLT<Eigen::MatrixXd> llt = maybe_op(ops, trace::Op::Potrf, m, m, 0, f::kSymmetric,
                                                   [&] { return Eigen::LLT<Eigen::MatrixXd>(S); });
  if (llt.info() != Eigen::Success) return gain;
  // Forward substitution L Y = H P = (P H^T)^T, back substitution L^T K^T = Y.
  const Eigen::MatrixXd HP = gain.PHt.transpose();
  const Eigen::MatrixXd Y = maybe_op(ops, trace::Op::Trsm, m, n, 0, f::kLower,
                                     [&] { return Eigen::MatrixXd(llt.matrixL().solve(HP)); });
  const Eigen::MatrixXd Kt = maybe_op(ops, trace::Op::Trsm, m, n, 0, f::kUpper,
                                      [&] { return Eigen::MatrixXd(llt.matrixU().solve(Y)); });
  gain.K = maybe_op(ops, trace::Op::Transpose, m, n, 0, 0,
                    [&] { return Eigen::MatrixXd(Kt.transpose()); });
  gain.ok = true;
  return gain;
}

bool update_covariance(Eigen::MatrixXd& P, const KalmanGain& gain, KernelRecorder* ops) {
  namespace f = trace::op_flags;
  const std::int64_t n = gain.K.rows(), m = gain.K.cols();
  Eigen::MatrixXd updated =
      maybe_op(ops, trace::Op::Gemm, n, n, m, f::kSymmetric | f::kTransposeB,
               [&] { return Eigen::MatrixXd(P - gain.K * gain.PHt.transpose()); });
  updated = maybe_op(ops, trace::Op::Transpose, n, n, 0, 0,
                     [&] { return Eigen::MatrixXd(0.5 * (updated + updated.transpose()).eval()); });
  if ((updated.diagonal().array() < 0).any()) return false;  // states without variance stay at 0
  P = std::move(updated);
  return true;
}

bool apply_update(VioState& state, const KalmanGain& gain, const Eigen::VectorXd& r,
                  KernelRecorder* ops) {
  if (!update_covariance(state.P, gain, ops)) return false;
  state.correct(gain.K * r);
  return true;
}

}  // namespace edx::backend::vio
