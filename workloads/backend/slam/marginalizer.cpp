#include "workloads/backend/slam/marginalizer.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <array>
#include <stdexcept>

#include "workloads/backend/slam/factors.hpp"

namespace edx::backend::slam {

using trace::Op;
namespace flags = trace::op_flags;

MarginalizationSystem linearize_marginalization(const Window& window, const SlamOptions& options) {
  if (window.keyframes.size() < 2) {
    throw std::logic_error("linearize_marginalization: < 2 keyframes");
  }
  MarginalizationSystem sys;
  const int d = window.state_dim;
  const KeyframeState& oldest = window.keyframes.front();

  // Landmarks anchored in the oldest keyframe, and the kept keyframes linked to the removed
  // variables (in window order).
  std::vector<const Landmark*> removed;
  std::vector<bool> linked(window.keyframes.size(), false);
  for (const auto& [id, l] : window.landmarks) {
    if (l.anchor_id != oldest.id) continue;
    removed.push_back(&l);
    sys.removed_tracks.push_back(l.track_id);
    for (const Observation& o : l.observations) {
      if (o.inlier) linked[static_cast<std::size_t>(window.slot(o.keyframe_id))] = true;
    }
  }
  if (d == 15 && window.keyframes[1].imu_from_previous) linked[1] = true;
  for (std::int64_t id : window.prior.keyframe_ids)
    linked[static_cast<std::size_t>(window.slot(id))] = true;
  linked[0] = false;
  std::vector<int> block_of(window.keyframes.size(), -1);
  for (std::size_t s = 1; s < linked.size(); ++s) {
    if (!linked[s]) continue;
    block_of[s] = static_cast<int>(sys.kept_slots.size());
    sys.kept_slots.push_back(static_cast<int>(s));
  }

  // Dense system over [rho_removed (m) | oldest (d) | kept keyframes | delta (when estimated)]:
  // the disparity offset is a kept variable, so what the removed right-image residuals (and the
  // previous prior) say about it stays in the new prior instead of being conditioned away.
  const int m = static_cast<int>(removed.size());
  sys.keeps_offset = options.estimate_disparity_offset;
  if (window.prior.has_offset && !sys.keeps_offset) {
    throw std::logic_error(
        "linearize_marginalization: prior has the disparity offset, not estimated");
  }
  const int r = static_cast<int>(sys.kept_slots.size()) * d + (sys.keeps_offset ? 1 : 0);
  sys.m = m;
  sys.d = d;
  sys.r = r;
  const int N = m + d + r;
  const int offset_at = sys.keeps_offset ? N - 1 : -1;  // delta's row (the last)
  Eigen::MatrixXd& H = sys.H;
  Eigen::VectorXd& b = sys.b;
  H = Eigen::MatrixXd::Zero(N, N);
  b = Eigen::VectorXd::Zero(N);
  auto pose_offset = [&](int slot) {
    return slot == 0 ? m : m + d + block_of[static_cast<std::size_t>(slot)] * d;
  };

  ReprojectionTerm t;
  for (int li = 0; li < m; ++li) {
    const Landmark& l = *removed[static_cast<std::size_t>(li)];
    if (!(l.inverse_depth > 0)) continue;
    for (const Observation& o : l.observations) {
      if (!o.inlier || !linearize_reprojection(window, l, o, options.pixel_sigma, t)) continue;
      // Rows past t.dim are zero in the residual and every Jacobian.
      const double w = huber(t.r.norm(), options.huber_threshold).weight;
      // Jacobian row block over [rho_li | oldest pose (6) | target pose (6) | delta].
      Eigen::Matrix<double, 4, 14> J = Eigen::Matrix<double, 4, 14>::Zero();
      J.col(0) = t.J_rho;
      if (!t.same_frame) {
        J.block<4, 6>(0, 1) = t.J_anchor;
        J.block<4, 6>(0, 7) = t.J_target;
      }
      J.col(13) = t.J_offset;
      const Eigen::Matrix<double, 14, 14> JtJ = w * J.transpose() * J;
      const Eigen::Matrix<double, 14, 1> Jtr = w * J.transpose() * t.r;
      // In the anchor only rho (and delta, through the right residual) enter.
      const int anchor = t.same_frame ? -1 : m;
      const int target = t.same_frame ? -1 : pose_offset(window.slot(o.keyframe_id));
      const int idx[4] = {li, anchor, target, offset_at};
      const int len[4] = {1, 6, 6, 1};
      const int col[4] = {0, 1, 7, 13};
      for (int p = 0; p < 4; ++p) {
        if (idx[p] < 0) continue;
        b.segment(idx[p], len[p]) -= Jtr.segment(col[p], len[p]);
        for (int q = 0; q < 4; ++q) {
          if (idx[q] < 0) continue;
          H.block(idx[p], idx[q], len[p], len[q]) += JtJ.block(col[p], col[q], len[p], len[q]);
        }
      }
    }
  }
  if (d == 15 && window.keyframes[1].imu_from_previous) {
    const Preintegration& pre = *window.keyframes[1].imu_from_previous;
    Eigen::Matrix<double, 15, 1> res;
    Eigen::Matrix<double, 15, 30> J;
    linearize_imu(pre, window.keyframes[0], window.keyframes[1], window.gravity, res, J);
    const Eigen::Matrix<double, 15, 15> info = imu_information(pre);
    const Eigen::Matrix<double, 30, 30> JtWJ = J.transpose() * info * J;
    const Eigen::Matrix<double, 30, 1> JtWr = J.transpose() * info * res;
    const int o[2] = {m, pose_offset(1)};
    for (int p = 0; p < 2; ++p) {
      b.segment<15>(o[p]) -= JtWr.segment<15>(15 * p);
      for (int q = 0; q < 2; ++q) H.block<15, 15>(o[p], o[q]) += JtWJ.block<15, 15>(15 * p, 15 * q);
    }
  }
  if (!window.prior.empty()) {
    const Prior& prior = window.prior;
    // (start in the prior's vector, start in H, length) of each of its variable blocks.
    std::vector<std::array<int, 3>> blocks;
    for (std::size_t k = 0; k < prior.keyframe_ids.size(); ++k) {
      blocks.push_back(
          {static_cast<int>(k) * d, pose_offset(window.slot(prior.keyframe_ids[k])), d});
    }
    if (prior.has_offset) {
      blocks.push_back({static_cast<int>(prior.keyframe_ids.size()) * d, offset_at, 1});
    }
    const Eigen::VectorXd res = prior.r0 + prior.J * window.prior_difference();
    const Eigen::MatrixXd JtJ = prior.J.transpose() * prior.J;
    const Eigen::VectorXd Jtr = prior.J.transpose() * res;
    for (const auto& [p0, h0, len0] : blocks) {
      b.segment(h0, len0) -= Jtr.segment(p0, len0);
      for (const auto& [p1, h1, len1] : blocks) {
        H.block(h0, h1, len0, len1) += JtJ.block(p0, p1, len0, len1);
      }
    }
  }

  return sys;
}

namespace {

template <class S>
using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

/// symmetric_pseudo_inverse in scalar type S.
template <class S>
Matrix<S> pseudo_inverse_in(const Matrix<S>& A) {
  const Matrix<S> sym = S(0.5) * (A + A.transpose());
  const Eigen::SelfAdjointEigenSolver<Matrix<S>> eig(sym);
  const Vector<S> inv_values = eig.eigenvalues().unaryExpr(
      [](S x) { return x > S(kPseudoInverseEpsilon) ? S(1) / x : S(0); });
  return eig.eigenvectors() * inv_values.asDiagonal() * eig.eigenvectors().transpose();
}

/// The offloadable part of the marginalization in scalar type S (the system rounded to S on the
/// way in, the prior widened to double on the way out): the removed variables eliminated from
/// the linearized system `sys`, and the prior J, r0 of what they said about the kept ones (left
/// empty when nothing kept is linked, r = 0).
template <class S>
void eliminate_in(const MarginalizationSystem& sys, KernelRecorder& recorder, Prior& prior) {
  const int m = sys.m, d = sys.d, r = sys.r;
  const int N = m + d + r;
  Matrix<S> H = sys.H.cast<S>();
  Vector<S> b = sys.b.cast<S>();

  // With an IMU, the removed keyframe's velocity and biases (9) go first: they couple only to
  // its pose and the kept states, never to landmarks, so eliminating them leaves A diagonal and
  // D the 6x6 pose block of Sec. VI (Schur complements compose, the prior is the same).
  //   H' = H_RR - H_RS H_SS^-1 H_SR,  b' = b_R - H_RS H_SS^-1 b_S
  if (d == 15) {
    const int n_rest = N - 9;
    std::vector<int> rest;
    for (int i = 0; i < N; ++i) {
      if (i < m + 6 || i >= m + 15) rest.push_back(i);
    }
    Matrix<S> H_RR(n_rest, n_rest), H_RS(n_rest, 9);
    Vector<S> b_R(n_rest);
    for (int i = 0; i < n_rest; ++i) {
      b_R(i) = b(rest[static_cast<std::size_t>(i)]);
      H_RS.row(i) = H.block(rest[static_cast<std::size_t>(i)], m + 6, 1, 9);
      for (int j = 0; j < n_rest; ++j) {
        H_RR(i, j) = H(rest[static_cast<std::size_t>(i)], rest[static_cast<std::size_t>(j)]);
      }
    }
    Eigen::Matrix<S, 9, 9> H_SS = H.template block<9, 9>(m + 6, m + 6);
    H_SS.diagonal().array() += S(1e-9);
    const Eigen::Matrix<S, 9, 1> b_S = b.template segment<9>(m + 6);
    const auto ldlt = recorder.op(Op::Ldlt, 9, 9, 0, flags::kSymmetric,
                                  [&] { return Eigen::LDLT<Eigen::Matrix<S, 9, 9>>(H_SS); });
    const Matrix<S> X = recorder.op(Op::Trsm, 9, n_rest, 0, flags::kSymmetric, [&] {
      return Matrix<S>(ldlt.solve(H_RS.transpose()));  // H_SS^-1 H_SR
    });
    const Vector<S> y = recorder.op(Op::Trsv, 9, 1, 0, flags::kSymmetric, [&] {
      return Vector<S>(ldlt.solve(b_S));  // H_SS^-1 b_S
    });
    H = recorder.op(Op::Gemm, n_rest, n_rest, 9, flags::kSymmetric,
                    [&] { return Matrix<S>(H_RR - H_RS * X); });
    b = recorder.op(Op::Gemm, n_rest, 1, 9, 0, [&] { return Vector<S>(b_R - H_RS * y); });
  }
  const int dm = 6;  // the removed keyframe's block left: its pose
  const int N_reduced = static_cast<int>(H.rows());
  const int r_reduced = N_reduced - m - dm;
  if (r_reduced != r) throw std::logic_error("marginalize_oldest: kept size mismatch");

  // The host inverts A_mm = [[A, B], [C, D]] as a general dense symmetric matrix, as
  // VINS-Mono's MarginalizationInfo does (eigen-decomposition, eigenvalues below
  // kPseudoInverseEpsilon dropped, so a landmark row without a usable observation carries no
  // information): O((m+6)^3). The flags record the structure (A diagonal, D 6x6) that the
  // accelerator's inverse unit exploits (paper Sec. VI-A); the host does not.
  const int mm = m + dm;
  const std::uint32_t inverse_flags = flags::kDiagonalBlock | flags::kSymmetric | flags::kBlock6x6;
  const Matrix<S> A_mm_inv = recorder.op(Op::Inverse, mm, mm, 0, inverse_flags, [&] {
    return pseudo_inverse_in<S>(H.topLeftCorner(mm, mm));
  });
  if (r == 0) return;  // nothing kept is linked: the removed variables leave no information
  const Matrix<S> A_mr = H.block(0, mm, mm, r);
  const Matrix<S> A_rm =
      recorder.op(Op::Transpose, mm, r, 0, 0, [&] { return Matrix<S>(A_mr.transpose()); });
  const Matrix<S> T = recorder.op(Op::Gemm, r, mm, mm, flags::kSymmetric,
                                  [&] { return Matrix<S>(A_rm * A_mm_inv); });
  Matrix<S> H_star = recorder.op(Op::Gemm, r, r, mm, flags::kSymmetric,
                                 [&] { return Matrix<S>(H.block(mm, mm, r, r) - T * A_mr); });
  H_star = S(0.5) * (H_star + H_star.transpose());
  const Vector<S> b_star = recorder.op(
      Op::Gemm, r, 1, mm, 0, [&] { return Vector<S>(b.segment(mm, r) - T * b.head(mm)); });
  const Eigen::LDLT<Matrix<S>> ldlt = recorder.op(Op::Ldlt, r, r, 0, flags::kSymmetric,
                                                  [&] { return Eigen::LDLT<Matrix<S>>(H_star); });
  const Vector<S> D_diag = ldlt.vectorD().cwiseMax(S(0));
  const Vector<S> sqrt_D = D_diag.cwiseSqrt();
  const Vector<S> inv_sqrt_D = sqrt_D.unaryExpr([](S x) { return x > S(1e-10) ? S(1) / x : S(0); });
  const Matrix<S> L = ldlt.matrixL();
  const Vector<S> Pb = ldlt.transpositionsP() * b_star;
  const Vector<S> Linv_Pb = recorder.op(Op::Trsv, r, 1, 0, flags::kLower,
                                        [&] { return Vector<S>(ldlt.matrixL().solve(Pb)); });
  const Matrix<S> J_prior = recorder.op(Op::Transpose, r, r, 0, flags::kLower, [&] {
    const Matrix<S> P = ldlt.transpositionsP() * Matrix<S>::Identity(r, r);
    return Matrix<S>(sqrt_D.asDiagonal() * L.transpose() * P);  // D^1/2 L^T P
  });
  const Vector<S> r0 = -(inv_sqrt_D.asDiagonal() * Linv_Pb);
  prior.J = J_prior.template cast<double>();
  prior.r0 = r0.template cast<double>();
}

}  // namespace

MarginalizationReport marginalize_oldest(Window& window, const SlamOptions& options,
                                         KernelRecorder& recorder) {
  if (window.keyframes.size() < 2) throw std::logic_error("marginalize_oldest: < 2 keyframes");
  auto kernel = recorder.kernel("marginalization", /*accelerable=*/true);
  const MarginalizationSystem sys = linearize_marginalization(window, options);
  const int m = sys.m, d = sys.d, r = sys.r;
  MarginalizationReport report;
  Prior prior;
  if (options.precision == trace::Precision::kFp32) {
    eliminate_in<float>(sys, recorder, prior);
  } else {
    eliminate_in<double>(sys, recorder, prior);
  }

  // Archive what leaves the window, then remove it and install the new prior.
  report.landmarks = m;
  report.kept_dim = r;
  report.removed = window.keyframes.front();
  for (std::int64_t track : sys.removed_tracks) {
    const Landmark& l = window.landmarks.at(track);
    report.removed_landmarks.push_back(l);
    report.removed_positions.push_back(window.landmark_world(l));
  }
  kernel.record().m = m;
  kernel.record().n = r;
  kernel.record().k = d;  // the removed keyframe's state size (6, or 15 with an IMU)
  for (int slot : sys.kept_slots) {
    prior.keyframe_ids.push_back(window.keyframes[static_cast<std::size_t>(slot)].id);
    prior.linearization_points.push_back(
        window.keyframes[static_cast<std::size_t>(slot)].navigation_state());
  }
  prior.has_offset = sys.keeps_offset && r > 0;
  prior.offset_linearization_px = window.disparity_offset_px;
  if (r == 0) prior.keyframe_ids.clear(), prior.linearization_points.clear();
  window.prior = std::move(prior);
  for (const Landmark& l : report.removed_landmarks) window.landmarks.erase(l.track_id);
  // Observations of other landmarks by the removed keyframe cannot exist (landmarks are only
  // observed from their anchor on), so the removed keyframe leaves no dangling reference.
  window.keyframes.pop_front();
  window.keyframes.front().imu_from_previous.reset();
  return report;
}

Eigen::MatrixXd symmetric_pseudo_inverse(const Eigen::MatrixXd& A) {
  return pseudo_inverse_in<double>(A);
}

}  // namespace edx::backend::slam
