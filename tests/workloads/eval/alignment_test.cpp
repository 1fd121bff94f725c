// Alignment on positions: Umeyama (se3, sim3) recovers known transforms exactly; posyaw recovers a
// yaw but not a roll.
#include "workloads/eval/alignment.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>

#include "tests/workloads/eval/eval_test_support.hpp"

namespace edx::eval {
namespace {

using testing::rot_x;
using testing::rot_y;
using testing::rot_z;

/// Points spread in 3-D (a helix), 3xN.
Eigen::Matrix3Xd helix_points() {
  const auto poses = testing::helix_poses();
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    points.col(static_cast<Eigen::Index>(i)) = poses[i].translation();
  }
  return points;
}

/// gt = s R est + t applied column-wise.
Eigen::Matrix3Xd transformed(const Eigen::Matrix3Xd& points, double s, const Eigen::Matrix3d& r,
                             const Eigen::Vector3d& t) {
  return ((s * r) * points).colwise() + t;
}

TEST(Alignment, Sim3RecoversScaleRotationAndTranslation) {
  const Eigen::Matrix3Xd est = helix_points();
  const Eigen::Matrix3d r = rot_z(0.7) * rot_y(-0.3) * rot_x(1.1);
  const Eigen::Vector3d t(10.0, -4.0, 2.5);
  const SimilarityTransform found =
      align_positions(est, transformed(est, 2.5, r, t), AlignmentMethod::kSim3);
  EXPECT_NEAR(found.scale, 2.5, 1e-12);
  EXPECT_TRUE(found.rotation.isApprox(r, 1e-12));
  EXPECT_TRUE(found.translation.isApprox(t, 1e-12));
  EXPECT_TRUE(found.apply(Eigen::Vector3d(1, 2, 3))
                  .isApprox(2.5 * r * Eigen::Vector3d(1, 2, 3) + t, 1e-12));
}

TEST(Alignment, Se3RecoversARigidTransformAndKeepsScaleOne) {
  const Eigen::Matrix3Xd est = helix_points();
  const Eigen::Matrix3d r = rot_x(-0.4) * rot_z(2.0);
  const Eigen::Vector3d t(-1.0, 3.0, 0.5);
  const SimilarityTransform rigid =
      align_positions(est, transformed(est, 1.0, r, t), AlignmentMethod::kSe3);
  EXPECT_EQ(rigid.scale, 1.0);
  EXPECT_TRUE(rigid.rotation.isApprox(r, 1e-12));
  EXPECT_TRUE(rigid.translation.isApprox(t, 1e-12));
  // A scaled target cannot be matched by se3: the scale stays 1.
  EXPECT_EQ(align_positions(est, transformed(est, 2.0, r, t), AlignmentMethod::kSe3).scale, 1.0);
}

TEST(Alignment, PosYawRecoversAYawRotation) {
  const Eigen::Matrix3Xd est = helix_points();
  const double yaw = 0.9;
  const Eigen::Vector3d t(3.0, -2.0, 1.0);
  const SimilarityTransform found =
      align_positions(est, transformed(est, 1.0, rot_z(yaw), t), AlignmentMethod::kPosYaw);
  EXPECT_TRUE(found.rotation.isApprox(rot_z(yaw), 1e-12));
  EXPECT_TRUE(found.translation.isApprox(t, 1e-12));
  // Also beyond +-90 degrees (the atan2 keeps the quadrant).
  const SimilarityTransform behind =
      align_positions(est, transformed(est, 1.0, rot_z(-2.8), t), AlignmentMethod::kPosYaw);
  EXPECT_TRUE(behind.rotation.isApprox(rot_z(-2.8), 1e-12));
}

TEST(Alignment, PosYawDoesNotAlignARoll) {
  const Eigen::Matrix3Xd est = helix_points();
  const Eigen::Matrix3Xd gt = transformed(est, 1.0, rot_x(0.2), Eigen::Vector3d::Zero());
  const SimilarityTransform posyaw = align_positions(est, gt, AlignmentMethod::kPosYaw);
  // The result is a rotation about z only: its z axis stays vertical.
  EXPECT_TRUE(posyaw.rotation.col(2).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  double residual = 0.0;
  for (Eigen::Index i = 0; i < est.cols(); ++i) {
    residual = std::max(residual, (posyaw.apply(Eigen::Vector3d(est.col(i))) - gt.col(i)).norm());
  }
  EXPECT_GT(residual, 0.1);  // the roll is left as error
  const SimilarityTransform se3 = align_positions(est, gt, AlignmentMethod::kSe3);
  EXPECT_TRUE(se3.rotation.isApprox(rot_x(0.2), 1e-12));  // while se3 finds it
}

TEST(Alignment, NoneIsTheIdentity) {
  const Eigen::Matrix3Xd est = helix_points();
  const SimilarityTransform none = align_positions(
      est, transformed(est, 3.0, rot_z(1.0), Eigen::Vector3d(1, 1, 1)), AlignmentMethod::kNone);
  EXPECT_EQ(none.scale, 1.0);
  EXPECT_EQ(none.rotation, Eigen::Matrix3d::Identity());
  EXPECT_EQ(none.translation, Eigen::Vector3d::Zero());
}

TEST(Alignment, TooFewPairsIsAnError) {
  const Eigen::Matrix3Xd two = helix_points().leftCols(2);
  EXPECT_THAT([&] { align_positions(two, two, AlignmentMethod::kSim3); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  "too few pose pairs for sim3 alignment: 2 (need at least 3)"));
  EXPECT_NO_THROW(align_positions(two, two, AlignmentMethod::kPosYaw));
  const Eigen::Matrix3Xd one = helix_points().leftCols(1);
  EXPECT_THROW(align_positions(one, one, AlignmentMethod::kPosYaw), std::runtime_error);
  EXPECT_NO_THROW(align_positions(one, one, AlignmentMethod::kNone));
}

TEST(Alignment, Sim3OfAStillEstimateIsAnError) {
  const Eigen::Matrix3Xd still = Eigen::Matrix3Xd::Ones(3, 5);
  EXPECT_THAT([&] { align_positions(still, helix_points().leftCols(5), AlignmentMethod::kSim3); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  "cannot align sim3: the estimated positions do not move (zero spread)"));
}

TEST(Alignment, MethodNames) {
  EXPECT_EQ(parse_alignment_method("posyaw"), AlignmentMethod::kPosYaw);
  EXPECT_EQ(alignment_method_name(AlignmentMethod::kSim3), "sim3");
  EXPECT_THROW(parse_alignment_method("7dof"), std::runtime_error);
}

}  // namespace
}  // namespace edx::eval
