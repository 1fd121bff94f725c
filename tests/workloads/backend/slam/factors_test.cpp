// Analytic reprojection Jacobians against central differences; the IMU residual vanishes on
// states consistent with the preintegrated motion; the Huber weights.
#include "workloads/backend/slam/factors.hpp"

#include <gtest/gtest.h>

#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {
namespace {

Window two_keyframe_window() {
  Window w;
  w.camera.width = 640;
  w.camera.height = 480;
  w.camera.fx = 450;
  w.camera.fy = 440;
  w.camera.cx = 320;
  w.camera.cy = 240;
  w.camera.baseline_m = 0.11;
  w.camera.T_body_left.linear() = so3_exp({0.1, -0.2, 1.5});
  w.camera.T_body_left.translation() = Eigen::Vector3d(0.05, -0.02, 0.01);
  KeyframeState a, b;
  a.id = 0;
  a.R = so3_exp({0.05, 0.1, -0.3});
  a.p = {1, 2, 0.5};
  b.id = 1;
  b.R = a.R * so3_exp({0.02, -0.05, 0.1});
  b.p = a.p + Eigen::Vector3d(0.3, -0.1, 0.05);
  w.keyframes.push_back(a);
  w.keyframes.push_back(b);
  return w;
}

TEST(ReprojectionFactor, JacobiansMatchCentralDifferences) {
  Window w = two_keyframe_window();
  Landmark l;
  l.track_id = 7;
  l.anchor_id = 0;
  l.bearing = {0.1, -0.05, 1};
  l.inverse_depth = 0.25;
  Observation o;
  o.keyframe_id = 1;
  o.left = {300, 250};
  o.right = Eigen::Vector2d(280, 250);
  l.observations.push_back(o);
  w.landmarks[7] = l;
  ReprojectionTerm t;
  ASSERT_TRUE(linearize_reprojection(w, w.landmarks[7], o, 1.5, t));
  ASSERT_EQ(t.dim, 4);
  const double h = 1e-6;
  for (int slot = 0; slot < 2; ++slot) {
    for (int c = 0; c < 6; ++c) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(6);
      d(c) = h;
      Window plus = w, minus = w;
      plus.keyframes[static_cast<std::size_t>(slot)].apply_increment(d, 6);
      minus.keyframes[static_cast<std::size_t>(slot)].apply_increment(-d, 6);
      ReprojectionTerm tp, tm;
      ASSERT_TRUE(linearize_reprojection(plus, plus.landmarks[7], o, 1.5, tp));
      ASSERT_TRUE(linearize_reprojection(minus, minus.landmarks[7], o, 1.5, tm));
      const Eigen::Vector4d numeric = (tp.r - tm.r) / (2 * h);
      const Eigen::Vector4d analytic = slot == 0 ? t.J_anchor.col(c) : t.J_target.col(c);
      EXPECT_LT((numeric - analytic).norm(), 1e-4 * (1 + analytic.norm()))
          << "slot " << slot << " column " << c;
    }
  }
  Window plus = w, minus = w;
  plus.landmarks[7].inverse_depth += h;
  minus.landmarks[7].inverse_depth -= h;
  ReprojectionTerm tp, tm;
  linearize_reprojection(plus, plus.landmarks[7], o, 1.5, tp);
  linearize_reprojection(minus, minus.landmarks[7], o, 1.5, tm);
  EXPECT_LT(((tp.r - tm.r) / (2 * h) - t.J_rho).norm(), 1e-4 * (1 + t.J_rho.norm()));
}

TEST(ReprojectionFactor, AnchorObservationConstrainsDepthOnly) {
  Window w = two_keyframe_window();
  Landmark l;
  l.anchor_id = 0;
  l.bearing = {0.1, -0.05, 1};
  l.inverse_depth = 0.25;  // 4 m: disparity = 450 * 0.11 / 4 = 12.375 px
  Observation o;
  o.keyframe_id = 0;
  o.left = {320 + 45, 240 - 22};
  o.right = Eigen::Vector2d(320 + 45 - 12.375, 240 - 22);
  ReprojectionTerm t;
  ASSERT_TRUE(linearize_reprojection(w, l, o, 1.0, t));
  EXPECT_TRUE(t.same_frame);
  EXPECT_EQ(t.dim, 2);
  EXPECT_NEAR(t.r(0), 0.0, 1e-9);
  EXPECT_NEAR(t.r(1), 0.0, 1e-9);
  // d u_r / d rho = -fx b.
  EXPECT_NEAR(t.J_rho(0), -450 * 0.11, 1e-9);
}

// The disparity offset delta shifts the predicted right x: a point at 4 m (12.375 px) measured
// at 11.375 px (delta = 1 px) is explained exactly with delta = 1, and dr/d delta = 1/sigma on
// the right x row only.
TEST(ReprojectionFactor, DisparityOffsetShiftsTheRightImage) {
  Window w = two_keyframe_window();
  Landmark l;
  l.anchor_id = 0;
  l.bearing = {0.1, -0.05, 1};
  l.inverse_depth = 0.25;
  Observation o;
  o.keyframe_id = 0;
  o.right = Eigen::Vector2d(320 + 45 - 11.375, 240 - 22);
  ReprojectionTerm t;
  ASSERT_TRUE(linearize_reprojection(w, l, o, 2.0, t));
  // delta = 0: predicted 1 px left of the measurement, whitened by sigma 2.
  EXPECT_NEAR(t.r(0), -1.0 / 2.0, 1e-9);
  w.disparity_offset_px = 1.0;
  ASSERT_TRUE(linearize_reprojection(w, l, o, 2.0, t));
  EXPECT_NEAR(t.r(0), 0.0, 1e-9);
  EXPECT_NEAR(t.r(1), 0.0, 1e-9);
  EXPECT_EQ(t.J_offset, Eigen::Vector4d(0.5, 0, 0, 0));
  // In another keyframe: the right x row is the third one.
  Window other = two_keyframe_window();
  Landmark m = l;
  m.bearing = {0.1, -0.05, 1};
  Observation q;
  q.keyframe_id = 1;
  q.left = {300, 250};
  q.right = Eigen::Vector2d(280, 250);
  ASSERT_TRUE(linearize_reprojection(other, m, q, 1.0, t));
  EXPECT_EQ(t.J_offset, Eigen::Vector4d(0, 0, 1, 0));
}

TEST(ImuFactor, ResidualVanishesOnConsistentStates) {
  const ImuNoiseDensities noise{1.7e-4, 2e-3, 1.9e-5, 3e-3};
  const Eigen::Vector3d g(0, 0, -9.81);
  const Eigen::Vector3d ba(0.01, -0.02, 0.03), bg(0.001, 0.002, -0.001);
  KeyframeState i;
  i.R = so3_exp({0.1, -0.2, 0.7});
  i.p = {1, 2, 3};
  i.v = {0.5, -0.3, 0.1};
  i.ba = ba;
  i.bg = bg;
  // Constant body rate and specific force; the state at j by exact integration in fine steps.
  const Eigen::Vector3d w(0.1, 0.3, -0.2), f(0.2, -0.1, 9.9);
  Preintegration pre(ba, bg, noise);
  KeyframeState j = i;
  for (int k = 0; k < 40; ++k) {
    const double dt = 0.005;
    pre.integrate(dt, f + ba, w + bg);
    const Eigen::Vector3d a_world = j.R * f + g;
    j.p += j.v * dt + 0.5 * a_world * dt * dt;
    j.v += a_world * dt;
    j.R = j.R * so3_exp(w * dt);
  }
  EXPECT_LT(imu_residual(pre, i, j, g).norm(), 1e-9);
  // Moving j off the consistent state shows up in the position residual: R_i^T dp.
  KeyframeState moved = j;
  moved.p += Eigen::Vector3d(0.1, 0, 0);
  const Eigen::Vector3d expected = i.R.transpose() * Eigen::Vector3d(0.1, 0, 0);
  EXPECT_LT((imu_residual(pre, i, moved, g).head<3>() - expected).norm(), 1e-9);
  Eigen::Matrix<double, 15, 1> r;
  Eigen::Matrix<double, 15, 30> J;
  linearize_imu(pre, i, j, g, r, J);
  EXPECT_LT((J.block<3, 3>(0, 15) - i.R.transpose()).norm(), 1e-6);              // d r_p / d p_j
  EXPECT_LT((J.block<3, 3>(9, 24) - Eigen::Matrix3d::Identity()).norm(), 1e-6);  // d r_ba / d ba_j
}

TEST(Huber, WeightsAndCost) {
  EXPECT_DOUBLE_EQ(huber(1.0, 2.0).weight, 1.0);
  EXPECT_DOUBLE_EQ(huber(1.0, 2.0).cost, 0.5);
  EXPECT_DOUBLE_EQ(huber(4.0, 2.0).weight, 0.5);
  EXPECT_DOUBLE_EQ(huber(4.0, 2.0).cost, 2.0 * (4.0 - 1.0));
}

}  // namespace
}  // namespace edx::backend::slam
