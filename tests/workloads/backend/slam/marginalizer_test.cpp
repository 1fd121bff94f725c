// Marginalization: the host's inverse against a dense inverse, and the prior it leaves
// against the Schur complement of the full normal equations computed independently (dense,
// from the factors' Jacobians), with and without the disparity offset delta as a kept variable,
// with the ops recorded with their sizes and structure flags; and the window LM using a prior
// that holds delta.
#include "workloads/backend/slam/marginalizer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "workloads/backend/slam/factors.hpp"
#include "workloads/backend/slam/lm_solver.hpp"
#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {
namespace {

// The host's general inverse of A_mm (diagonal A, 6x6 D): equals Eigen's LU inverse, and drops
// a direction without information instead of blowing up.
TEST(SymmetricPseudoInverse, MatchesDenseInverseAndDropsNullDirections) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0, 1);
  const int m = 9, d = 6;
  Eigen::MatrixXd J(40, m + d);
  for (int r = 0; r < J.rows(); ++r) {
    for (int c = 0; c < J.cols(); ++c) J(r, c) = n(rng);
  }
  Eigen::MatrixXd H = J.transpose() * J;
  H.topLeftCorner(m, m) = Eigen::MatrixXd(H.topLeftCorner(m, m).diagonal().asDiagonal());
  H.topLeftCorner(m, m).diagonal().array() += 50.0;  // keep it positive definite
  const Eigen::MatrixXd inv = symmetric_pseudo_inverse(H);
  EXPECT_LT((inv - H.inverse()).norm(), 1e-9 * H.inverse().norm());

  // A landmark without any usable observation: an empty row and column.
  H.row(2).setZero();
  H.col(2).setZero();
  const Eigen::MatrixXd pinv = symmetric_pseudo_inverse(H);
  EXPECT_LT(pinv.row(2).norm(), 1e-12 * pinv.norm());
  Eigen::MatrixXd expected_identity = Eigen::MatrixXd::Identity(m + d, m + d);
  expected_identity(2, 2) = 0;
  EXPECT_LT((pinv * H - expected_identity).norm(), 1e-9);
}

/// Window of three keyframes 0.3 m apart looking at a wall of landmarks anchored in the first
/// two, observed in every later keyframe with exact pixels plus a perturbation.
Window test_window() {
  Window w;
  w.camera.width = 640;
  w.camera.height = 480;
  w.camera.fx = w.camera.fy = 400;
  w.camera.cx = 320;
  w.camera.cy = 240;
  w.camera.baseline_m = 0.1;
  w.state_dim = 6;
  for (int k = 0; k < 3; ++k) {
    KeyframeState kf;
    kf.id = k;
    kf.p = {0.3 * k, 0.02 * k, 0};
    kf.R = so3_exp({0, 0.01 * k, 0});
    w.keyframes.push_back(kf);
  }
  std::int64_t track = 0;
  for (int anchor = 0; anchor < 2; ++anchor) {
    for (int i = 0; i < 12; ++i) {
      Landmark l;
      l.track_id = track++;
      l.anchor_id = anchor;
      l.bearing = {-0.4 + 0.07 * i, 0.2 * ((i % 3) - 1), 1};
      l.inverse_depth = 1.0 / (3.0 + 0.2 * i);
      w.landmarks[l.track_id] = l;
      for (int k = anchor; k < 3; ++k) {
        Observation o;
        o.keyframe_id = k;
        w.landmarks[l.track_id].observations.push_back(o);
      }
    }
  }
  // Pixels: exact projections, shifted a little so the residuals are not zero.
  for (auto& [id, l] : w.landmarks) {
    for (Observation& o : l.observations) {
      o.left = {0, 0};
      o.right = Eigen::Vector2d(0, 0);
      ReprojectionTerm t;
      linearize_reprojection(w, l, o, 1.0, t);
      if (t.same_frame) {
        o.left = {w.camera.fx * l.bearing.x() + w.camera.cx,
                  w.camera.fy * l.bearing.y() + w.camera.cy};
        o.right = Eigen::Vector2d(t.r(0) + 0.3, t.r(1));
      } else {
        o.left = {t.r(0) + 0.2 * ((id % 2) ? 1 : -1), t.r(1) - 0.1};
        o.right = Eigen::Vector2d(t.r(2) + 0.1, t.r(3));
      }
    }
  }
  // A prior on the first keyframe (gauge).
  w.prior.keyframe_ids = {0};
  w.prior.linearization_points = {w.keyframes[0].navigation_state()};
  w.prior.J = Eigen::MatrixXd::Identity(6, 6) * 100;
  w.prior.r0 = Eigen::VectorXd::Constant(6, 0.01);
  return w;
}

/// H* and b* of the Schur complement computed densely: the system over
/// [rho of landmarks anchored in the oldest keyframe | keyframes in window order | delta
/// (with_offset)] from every factor's Jacobian (no loss), the IMU factor oldest-next when d = 15
/// and the window's prior (whose keyframes sit at their linearization points), then the removed
/// block [rho | oldest] eliminated with a dense inverse.
struct DenseReference {
  Eigen::MatrixXd H_star;
  Eigen::VectorXd b_star;
  int m = 0;
};

DenseReference dense_reference(const Window& w, bool with_offset) {
  const int d = w.state_dim;
  const int K = static_cast<int>(w.keyframes.size());
  std::vector<std::int64_t> removed;
  for (const auto& [id, l] : w.landmarks) {
    if (l.anchor_id == w.keyframes.front().id) removed.push_back(id);
  }
  const int m = static_cast<int>(removed.size());
  const int N = m + K * d + (with_offset ? 1 : 0), off = N - 1;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(N);
  for (int li = 0; li < m; ++li) {
    const Landmark& l = w.landmarks.at(removed[static_cast<std::size_t>(li)]);
    for (const Observation& o : l.observations) {
      ReprojectionTerm t;
      EXPECT_TRUE(linearize_reprojection(w, l, o, 1.0, t));
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(4, N);
      J.col(li) = t.J_rho;
      if (!t.same_frame) {
        J.block(0, m, 4, 6) = t.J_anchor;
        J.block(0, m + d * w.slot(o.keyframe_id), 4, 6) += t.J_target;
      }
      if (with_offset) J.col(off) = t.J_offset;
      H += J.transpose() * J;
      b -= J.transpose() * t.r;
    }
  }
  if (d == 15) {
    Eigen::Matrix<double, 15, 1> r;
    Eigen::Matrix<double, 15, 30> J;
    linearize_imu(*w.keyframes[1].imu_from_previous, w.keyframes[0], w.keyframes[1], w.gravity, r,
                  J);
    const Eigen::Matrix<double, 15, 15> info = imu_information(*w.keyframes[1].imu_from_previous);
    H.block(m, m, 30, 30) += J.transpose() * info * J;
    b.segment(m, 30) -= J.transpose() * info * r;
  }
  // The prior: keyframe columns at their window position, delta's last; dx = [0 | delta - delta0].
  const Prior& prior = w.prior;
  const int np = static_cast<int>(prior.J.cols());
  Eigen::MatrixXd Jp = Eigen::MatrixXd::Zero(prior.J.rows(), N);
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(np);
  for (std::size_t k = 0; k < prior.keyframe_ids.size(); ++k) {
    Jp.middleCols(m + d * w.slot(prior.keyframe_ids[k]), d) =
        prior.J.middleCols(static_cast<int>(k) * d, d);
  }
  if (prior.has_offset) {
    Jp.col(off) = prior.J.col(np - 1);
    dx(np - 1) = w.disparity_offset_px - prior.offset_linearization_px;
  }
  H += Jp.transpose() * Jp;
  b -= Jp.transpose() * (prior.r0 + prior.J * dx);
  const int mm = m + d, r = N - mm;
  const Eigen::MatrixXd A_mm_inv = H.topLeftCorner(mm, mm).inverse();
  DenseReference ref;
  ref.m = m;
  ref.H_star =
      H.bottomRightCorner(r, r) - H.bottomLeftCorner(r, mm) * A_mm_inv * H.topRightCorner(mm, r);
  ref.b_star = b.tail(r) - H.bottomLeftCorner(r, mm) * A_mm_inv * b.head(mm);
  return ref;
}

void expect_prior_matches(const Prior& prior, const DenseReference& ref) {
  ASSERT_EQ(prior.J.cols(), ref.H_star.cols());
  const Eigen::MatrixXd JtJ = prior.J.transpose() * prior.J;
  EXPECT_LT((JtJ - ref.H_star).norm(), 1e-6 * ref.H_star.norm());
  EXPECT_LT((prior.J.transpose() * prior.r0 + ref.b_star).norm(), 1e-6 * (1 + ref.b_star.norm()));
}

TEST(Marginalization, PriorIsTheSchurComplementOfTheRemovedBlockWithoutTheOffset) {
  Window w = test_window();
  SlamOptions options;
  options.huber_threshold = 1e6;  // plain least squares: the dense reference has no loss
  options.estimate_disparity_offset = false;
  const DenseReference ref = dense_reference(w, false);

  KernelRecorder recorder;
  const MarginalizationReport report = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report.landmarks, 12);
  EXPECT_EQ(report.kept_dim, 12);
  ASSERT_EQ(w.keyframes.size(), 2u);
  EXPECT_EQ(w.keyframes.front().id, 1);
  EXPECT_EQ(w.landmarks.size(), 12u);  // the ones anchored in keyframe 1 remain
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{1, 2}));
  EXPECT_FALSE(w.prior.has_offset);
  expect_prior_matches(w.prior, ref);

  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  EXPECT_EQ(kernels[0].kernel, "marginalization");
  EXPECT_TRUE(kernels[0].accelerable);
  EXPECT_EQ(kernels[0].m, 12);
  EXPECT_EQ(kernels[0].n, 12);
  ASSERT_FALSE(kernels[0].ops.empty());
  const trace::OpRecord& inverse = kernels[0].ops.front();
  EXPECT_EQ(inverse.op, trace::Op::Inverse);
  EXPECT_EQ(inverse.m, 18);
  EXPECT_EQ(inverse.flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                               trace::op_flags::kSymmetric);
}

// At fp32 the elimination runs in single: the prior is the same Schur complement to single's
// precision, its entries are floats, and the kernel records the same ops.
TEST(Marginalization, Fp32PriorIsTheSchurComplementToSinglePrecision) {
  Window w64 = test_window(), w32 = test_window();
  SlamOptions options;
  options.huber_threshold = 1e6;
  options.estimate_disparity_offset = false;
  const DenseReference ref = dense_reference(w64, false);
  KernelRecorder recorder;
  marginalize_oldest(w64, options, recorder);
  options.precision = trace::Precision::kFp32;
  marginalize_oldest(w32, options, recorder);
  const Eigen::MatrixXd JtJ = w32.prior.J.transpose() * w32.prior.J;
  const double relative = (JtJ - ref.H_star).norm() / ref.H_star.norm();
  EXPECT_LT(relative, 1e-3);
  EXPECT_GT((w32.prior.J - w64.prior.J).norm(), 0.0);  // not double's arithmetic
  for (Eigen::Index i = 0; i < w32.prior.J.size(); ++i) {
    const double v = w32.prior.J.data()[i];
    EXPECT_EQ(v, static_cast<double>(static_cast<float>(v)));
  }
  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 2u);
  ASSERT_EQ(kernels[0].ops.size(), kernels[1].ops.size());
  for (std::size_t i = 0; i < kernels[0].ops.size(); ++i) {
    EXPECT_EQ(kernels[0].ops[i].op, kernels[1].ops[i].op);
    EXPECT_EQ(kernels[0].ops[i].m, kernels[1].ops[i].m);
  }
}

// delta kept: the removed landmarks' right residuals (including those in their anchor, which
// only depend on rho and delta) and a previous prior that holds delta all enter the new prior,
// which is over [kf1 | kf2 | delta] (13). The removed block, and so the structured inverse,
// stays [rho (12) | kf0 (6)].
TEST(Marginalization, KeepsTheDisparityOffsetInThePrior) {
  Window w = test_window();
  w.disparity_offset_px = 0.4;
  // The gauge prior extended by delta, with a cross term so that both blocks are mixed.
  w.prior.has_offset = true;
  w.prior.offset_linearization_px = 0.1;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(7, 7);
  J.topLeftCorner(6, 6) = w.prior.J;
  J(6, 6) = 2.0;
  J(6, 0) = 0.5;
  w.prior.J = J;
  w.prior.r0 = Eigen::VectorXd::Constant(7, 0.01);
  SlamOptions options;
  options.huber_threshold = 1e6;
  ASSERT_TRUE(options.estimate_disparity_offset);
  const DenseReference ref = dense_reference(w, true);
  ASSERT_EQ(ref.H_star.rows(), 13);
  EXPECT_GT(ref.H_star(12, 12), 1.0);  // the removed right residuals inform delta

  KernelRecorder recorder;
  const MarginalizationReport report = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report.kept_dim, 13);
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{1, 2}));
  EXPECT_TRUE(w.prior.has_offset);
  EXPECT_EQ(w.prior.offset_linearization_px, 0.4);
  expect_prior_matches(w.prior, ref);

  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  EXPECT_EQ(kernels[0].m, 12);
  EXPECT_EQ(kernels[0].n, 13);
  EXPECT_EQ(kernels[0].k, 6);
  // Ops in order: inverse (m + 6), transpose (A_mr), gemm (A_rm A_mm^-1), gemm (H*), gemm (b*),
  // ldlt (H*), trsv (r0), transpose (J), with the kept size n = 13.
  const std::vector<trace::OpRecord>& ops = kernels[0].ops;
  ASSERT_EQ(ops.size(), 8u);
  const trace::Op order[8] = {trace::Op::Inverse, trace::Op::Transpose, trace::Op::Gemm,
                              trace::Op::Gemm,    trace::Op::Gemm,      trace::Op::Ldlt,
                              trace::Op::Trsv,    trace::Op::Transpose};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(ops[i].op, order[i]) << "op " << i;
  EXPECT_EQ(ops[0].m, 18);
  EXPECT_EQ(ops[0].flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                              trace::op_flags::kSymmetric);
  EXPECT_EQ(ops[1].m, 18);
  EXPECT_EQ(ops[1].n, 13);
  EXPECT_EQ(ops[3].m, 13);
  EXPECT_EQ(ops[3].n, 13);
  EXPECT_EQ(ops[3].k, 18);
  EXPECT_EQ(ops[4].n, 1);
  EXPECT_EQ(ops[5].m, 13);
  EXPECT_EQ(ops[6].m, 13);
  EXPECT_EQ(ops[7].m, 13);

  // A second marginalization consumes that prior (kf1 removed, kf2 and delta kept), with delta
  // moved away from the prior's linearization point.
  w.disparity_offset_px = 0.5;
  const DenseReference ref2 = dense_reference(w, true);
  ASSERT_EQ(ref2.H_star.rows(), 7);
  const MarginalizationReport report2 = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report2.kept_dim, 7);
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{2}));
  EXPECT_TRUE(w.prior.has_offset);
  expect_prior_matches(w.prior, ref2);
}

TEST(Marginalization, WithImuEliminatesSpeedAndBiasFirstAndMatchesTheDenseSchurComplement) {
  Window w = test_window();
  w.state_dim = 15;
  w.disparity_offset_px = -0.2;
  const ImuNoiseDensities noise{1.7e-4, 2e-3, 1.9e-5, 3e-3};
  for (std::size_t k = 0; k < 3; ++k) w.keyframes[k].v = {0.3 / 0.2, 0.1, 0};
  for (std::size_t k = 1; k < 3; ++k) {
    Preintegration pre(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), noise);
    for (int i = 0; i < 40; ++i) pre.integrate(0.005, {0.05, 0.02, 9.81}, {0, 0.05, 0.01});
    w.keyframes[k].imu_from_previous = pre;
  }
  w.prior.linearization_points = {w.keyframes[0].navigation_state()};
  w.prior.J = Eigen::MatrixXd::Identity(15, 15) * 100;
  w.prior.r0 = Eigen::VectorXd::Constant(15, 0.01);
  SlamOptions options;
  options.huber_threshold = 1e6;
  const DenseReference ref = dense_reference(w, true);  // over [kf1 | kf2 | delta] (31)

  KernelRecorder recorder;
  const MarginalizationReport report = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report.kept_dim, 31);
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{1, 2}));
  EXPECT_TRUE(w.prior.has_offset);
  expect_prior_matches(w.prior, ref);
  EXPECT_FALSE(w.keyframes.front().imu_from_previous.has_value());
  EXPECT_TRUE(w.keyframes.back().imu_from_previous.has_value());

  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  EXPECT_EQ(kernels[0].k, 15);
  EXPECT_EQ(kernels[0].n, 31);
  ASSERT_GE(kernels[0].ops.size(), 6u);
  EXPECT_EQ(kernels[0].ops[0].op, trace::Op::Ldlt);
  EXPECT_EQ(kernels[0].ops[0].m, 9);
  EXPECT_EQ(kernels[0].ops[1].n, 12 + 6 + 31);  // H_SS^-1 H_SR over everything else
  EXPECT_EQ(kernels[0].ops[5].op, trace::Op::Inverse);
  EXPECT_EQ(kernels[0].ops[5].m, 12 + 6);
  EXPECT_EQ(kernels[0].ops[5].flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                                         trace::op_flags::kSymmetric);
}

// The window LM with a prior on [kf0 | delta] and no landmarks: the offset's cost is
// 1/2 (r0 + j (delta - delta0))^2 + 1/2 (delta / sigma)^2, minimized in closed form at
//   delta* = (j^2 delta0 - j r0) / (j^2 + 1/sigma^2).
TEST(Marginalization, WindowLmUsesTheOffsetOfThePrior) {
  Window w = test_window();
  w.landmarks.clear();
  w.keyframes.resize(1);
  const double j = 3.0, r0 = 0.6, delta0 = 1.5;
  w.prior.has_offset = true;
  w.prior.offset_linearization_px = delta0;
  w.prior.J = Eigen::MatrixXd::Identity(7, 7) * 100;
  w.prior.J(6, 6) = j;
  w.prior.r0 = Eigen::VectorXd::Zero(7);
  w.prior.r0(6) = r0;
  SlamOptions options;
  options.disparity_offset_sigma_px = 2;
  // Cost at delta = 0: the prior's 1/2 (r0 - j delta0)^2, the zero-mean prior nothing.
  EXPECT_NEAR(window_cost(w, options), 0.5 * (r0 - j * delta0) * (r0 - j * delta0), 1e-12);
  KernelRecorder recorder;
  optimize_window(w, options, recorder);
  const double s2 = 1.0 / (2.0 * 2.0);
  EXPECT_NEAR(w.disparity_offset_px, (j * j * delta0 - j * r0) / (j * j + s2), 1e-3);
  EXPECT_NEAR(w.keyframes[0].p.norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace edx::backend::slam
