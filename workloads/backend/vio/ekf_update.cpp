#include "workloads/backend/vio/ekf_update.hpp"

#include <Eigen/Cholesky>

namespace edx::backend::vio {
namespace {

template <class S>
using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;

/// Runs fn, recording it as `op` when a recorder is given.
template <class Fn>
auto maybe_op(KernelRecorder* ops, trace::Op op, std::int64_t m, std::int64_t n, std::int64_t k,
              std::uint32_t flags, Fn&& fn) {
  if (ops) return ops->op(op, m, n, k, flags, std::forward<Fn>(fn));
  return fn();
}

/// kalman_gain in scalar type S (double: the host's arithmetic, bit for bit).
template <class S>
KalmanGain kalman_gain_in(const Eigen::MatrixXd& P_host, const Eigen::MatrixXd& H_host,
                          const Eigen::VectorXd& noise_var, KernelRecorder* ops) {
  namespace f = trace::op_flags;
  const Matrix<S> P = P_host.cast<S>(), H = H_host.cast<S>();
  const std::int64_t m = H.rows(), n = H.cols();
  KalmanGain gain;
  // P H^T (n x m), then S = H (P H^T) + R (m x m, symmetric).
  const Matrix<S> PHt = maybe_op(ops, trace::Op::Gemm, n, m, n, f::kSymmetric | f::kTransposeB,
                                 [&] { return Matrix<S>(P * H.transpose()); });
  Matrix<S> innovation =
      maybe_op(ops, trace::Op::Gemm, m, m, n, f::kSymmetric, [&] { return Matrix<S>(H * PHt); });
  innovation.diagonal() += noise_var.cast<S>();
  // S = L L^T.
  const Eigen::LLT<Matrix<S>> llt = maybe_op(ops, trace::Op::Potrf, m, m, 0, f::kSymmetric,
                                             [&] { return Eigen::LLT<Matrix<S>>(innovation); });
  gain.PHt = PHt.template cast<double>();
  if (llt.info() != Eigen::Success) return gain;
  // Forward substitution L Y = H P = (P H^T)^T, back substitution L^T K^T = Y.
  const Matrix<S> HP = PHt.transpose();
  const Matrix<S> Y = maybe_op(ops, trace::Op::Trsm, m, n, 0, f::kLower,
                               [&] { return Matrix<S>(llt.matrixL().solve(HP)); });
  const Matrix<S> Kt = maybe_op(ops, trace::Op::Trsm, m, n, 0, f::kUpper,
                                [&] { return Matrix<S>(llt.matrixU().solve(Y)); });
  gain.K = maybe_op(ops, trace::Op::Transpose, m, n, 0, 0, [&] {
             return Matrix<S>(Kt.transpose());
           }).template cast<double>();
  gain.ok = true;
  return gain;
}

/// update_covariance's new P in scalar type S; false when a diagonal entry turns negative.
template <class S>
bool update_covariance_in(Eigen::MatrixXd& P_host, const KalmanGain& gain, KernelRecorder* ops) {
  namespace f = trace::op_flags;
  const std::int64_t n = gain.K.rows(), m = gain.K.cols();
  const Matrix<S> P = P_host.cast<S>(), K = gain.K.cast<S>(), PHt = gain.PHt.cast<S>();
  Matrix<S> updated = maybe_op(ops, trace::Op::Gemm, n, n, m, f::kSymmetric | f::kTransposeB,
                               [&] { return Matrix<S>(P - K * PHt.transpose()); });
  updated = maybe_op(ops, trace::Op::Transpose, n, n, 0, 0,
                     [&] { return Matrix<S>((S(0.5) * (updated + updated.transpose())).eval()); });
  if ((updated.diagonal().array() < 0).any()) return false;  // states without variance stay at 0
  P_host = updated.template cast<double>();
  return true;
}

}  // namespace

KalmanGain kalman_gain(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H,
                       const Eigen::VectorXd& noise_var, KernelRecorder* ops,
                       trace::Precision precision) {
  return precision == trace::Precision::kFp32 ? kalman_gain_in<float>(P, H, noise_var, ops)
                                              : kalman_gain_in<double>(P, H, noise_var, ops);
}

bool update_covariance(Eigen::MatrixXd& P, const KalmanGain& gain, KernelRecorder* ops,
                       trace::Precision precision) {
  return precision == trace::Precision::kFp32 ? update_covariance_in<float>(P, gain, ops)
                                              : update_covariance_in<double>(P, gain, ops);
}

bool apply_update(VioState& state, const KalmanGain& gain, const Eigen::VectorXd& r,
                  KernelRecorder* ops, trace::Precision precision) {
  if (!update_covariance(state.P, gain, ops, precision)) return false;
  state.correct(gain.K * r);
  return true;
}

}  // namespace edx::backend::vio
