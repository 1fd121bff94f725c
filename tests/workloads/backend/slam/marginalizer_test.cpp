// Marginalization: the structured inverse against a dense inverse, and the prior it leaves
// against the Schur complement of the full normal equations computed independently (dense,
// from the factors' Jacobians), with the ops recorded with their sizes and structure flags.
#include "workloads/backend/slam/marginalizer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "workloads/backend/slam/factors.hpp"
#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {
namespace {

TEST(StructuredInverse, MatchesDenseInverse) {
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
  const Eigen::MatrixXd inv = structured_inverse(H.topLeftCorner(m, m).diagonal(),
                                                 H.topRightCorner(m, d), H.bottomRightCorner(d, d));
  EXPECT_LT((inv - H.inverse()).norm(), 1e-9 * H.inverse().norm());
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

TEST(Marginalization, PriorIsTheSchurComplementOfTheRemovedBlock) {
  Window w = test_window();
  SlamOptions options;
  options.huber_threshold = 1e6;  // plain least squares: the dense reference below has no loss
  // Dense reference over [rho of landmarks anchored in kf 0 | kf0 | kf1 | kf2].
  std::vector<std::int64_t> removed;
  for (const auto& [id, l] : w.landmarks) {
    if (l.anchor_id == 0) removed.push_back(id);
  }
  const int m = static_cast<int>(removed.size()), N = m + 18;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(N);
  for (int li = 0; li < m; ++li) {
    const Landmark& l = w.landmarks.at(removed[static_cast<std::size_t>(li)]);
    for (const Observation& o : l.observations) {
      ReprojectionTerm t;
      ASSERT_TRUE(linearize_reprojection(w, l, o, options.pixel_sigma, t));
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(t.dim, N);
      J.col(li) = t.J_rho.head(t.dim);
      if (!t.same_frame) {
        J.block(0, m, t.dim, 6) = t.J_anchor.topRows(t.dim);
        J.block(0, m + 6 * static_cast<int>(o.keyframe_id), t.dim, 6) += t.J_target.topRows(t.dim);
      }
      H += J.transpose() * J;
      b -= J.transpose() * t.r.head(t.dim);
    }
  }
  H.block(m, m, 6, 6) += w.prior.J.transpose() * w.prior.J;
  b.segment(m, 6) -= w.prior.J.transpose() * w.prior.r0;
  const int mm = m + 6;
  const Eigen::MatrixXd H_star =
      H.bottomRightCorner(12, 12) -
      H.bottomLeftCorner(12, mm) * H.topLeftCorner(mm, mm).inverse() * H.topRightCorner(mm, 12);
  const Eigen::VectorXd b_star =
      b.tail(12) - H.bottomLeftCorner(12, mm) * H.topLeftCorner(mm, mm).inverse() * b.head(mm);

  KernelRecorder recorder;
  const MarginalizationReport report = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report.landmarks, 12);
  EXPECT_EQ(report.kept_dim, 12);
  ASSERT_EQ(w.keyframes.size(), 2u);
  EXPECT_EQ(w.keyframes.front().id, 1);
  EXPECT_EQ(w.landmarks.size(), 12u);  // the ones anchored in keyframe 1 remain
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{1, 2}));
  const Eigen::MatrixXd JtJ = w.prior.J.transpose() * w.prior.J;
  EXPECT_LT((JtJ - H_star).norm(), 1e-6 * H_star.norm());
  EXPECT_LT((w.prior.J.transpose() * w.prior.r0 + b_star).norm(), 1e-6 * (1 + b_star.norm()));

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
  bool has_gemm = false, has_ldlt = false, has_trsv = false;
  for (const trace::OpRecord& op : kernels[0].ops) {
    has_gemm |= op.op == trace::Op::Gemm && op.m == 12 && op.k == 18;
    has_ldlt |= op.op == trace::Op::Ldlt && op.m == 12;
    has_trsv |= op.op == trace::Op::Trsv && op.m == 12;
  }
  EXPECT_TRUE(has_gemm);
  EXPECT_TRUE(has_ldlt);
  EXPECT_TRUE(has_trsv);
}

}  // namespace
}  // namespace edx::backend::slam

namespace edx::backend::slam {
namespace {

TEST(Marginalization, WithImuEliminatesSpeedAndBiasFirstAndMatchesTheDenseSchurComplement) {
  Window w = test_window();
  w.state_dim = 15;
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

  // Dense reference over [rho (m) | kf0 | kf1 | kf2] (15 each).
  std::vector<std::int64_t> removed;
  for (const auto& [id, l] : w.landmarks) {
    if (l.anchor_id == 0) removed.push_back(id);
  }
  const int m = static_cast<int>(removed.size()), N = m + 45;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(N);
  for (int li = 0; li < m; ++li) {
    const Landmark& l = w.landmarks.at(removed[static_cast<std::size_t>(li)]);
    for (const Observation& o : l.observations) {
      ReprojectionTerm t;
      ASSERT_TRUE(linearize_reprojection(w, l, o, options.pixel_sigma, t));
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(4, N);
      J.col(li) = t.J_rho;
      if (!t.same_frame) {
        J.block(0, m, 4, 6) = t.J_anchor;
        J.block(0, m + 15 * static_cast<int>(o.keyframe_id), 4, 6) += t.J_target;
      }
      H += J.transpose() * J;
      b -= J.transpose() * t.r;
    }
  }
  Eigen::Matrix<double, 15, 1> r;
  Eigen::Matrix<double, 15, 30> J;
  linearize_imu(*w.keyframes[1].imu_from_previous, w.keyframes[0], w.keyframes[1], w.gravity, r, J);
  const Eigen::Matrix<double, 15, 15> info = imu_information(*w.keyframes[1].imu_from_previous);
  H.block(m, m, 30, 30) += J.transpose() * info * J;
  b.segment(m, 30) -= J.transpose() * info * r;
  H.block(m, m, 15, 15) += w.prior.J.transpose() * w.prior.J;
  b.segment(m, 15) -= w.prior.J.transpose() * w.prior.r0;
  const int mm = m + 15;
  const Eigen::MatrixXd A_mm_inv = H.topLeftCorner(mm, mm).inverse();
  const Eigen::MatrixXd H_star = H.bottomRightCorner(30, 30) -
                                 H.bottomLeftCorner(30, mm) * A_mm_inv * H.topRightCorner(mm, 30);
  const Eigen::VectorXd b_star = b.tail(30) - H.bottomLeftCorner(30, mm) * A_mm_inv * b.head(mm);

  KernelRecorder recorder;
  const MarginalizationReport report = marginalize_oldest(w, options, recorder);
  EXPECT_EQ(report.kept_dim, 30);
  ASSERT_EQ(w.prior.keyframe_ids, (std::vector<std::int64_t>{1, 2}));
  EXPECT_LT((w.prior.J.transpose() * w.prior.J - H_star).norm(), 1e-6 * H_star.norm());
  EXPECT_LT((w.prior.J.transpose() * w.prior.r0 + b_star).norm(), 1e-6 * (1 + b_star.norm()));
  EXPECT_FALSE(w.keyframes.front().imu_from_previous.has_value());
  EXPECT_TRUE(w.keyframes.back().imu_from_previous.has_value());

  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  EXPECT_EQ(kernels[0].k, 15);
  ASSERT_GE(kernels[0].ops.size(), 6u);
  EXPECT_EQ(kernels[0].ops[0].op, trace::Op::Ldlt);
  EXPECT_EQ(kernels[0].ops[0].m, 9);
  EXPECT_EQ(kernels[0].ops[5].op, trace::Op::Inverse);
  EXPECT_EQ(kernels[0].ops[5].m, 12 + 6);
  EXPECT_EQ(kernels[0].ops[5].flags, trace::op_flags::kDiagonalBlock | trace::op_flags::kBlock6x6 |
                                         trace::op_flags::kSymmetric);
}

}  // namespace
}  // namespace edx::backend::slam
