// interpolate_ground_truth against hand-computed poses.
#include <gtest/gtest.h>

#include <cmath>

#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {
namespace {

GroundTruthPose pose_at(TimestampNs t, const Eigen::Vector3d& p, double yaw_rad) {
  GroundTruthPose pose;
  pose.t_ns = t;
  pose.T_world_body.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).matrix();
  pose.T_world_body.translation() = p;
  return pose;
}

std::vector<GroundTruthPose> two_poses() {
  auto a = pose_at(1000, {0, 0, 0}, 0);
  auto b = pose_at(1010, {10, 20, -10}, M_PI / 2);
  a.velocity_m_s = Eigen::Vector3d(1, 0, 0);
  b.velocity_m_s = Eigen::Vector3d(3, 4, 0);
  return {a, b};
}

TEST(InterpolateGroundTruth, LinearPositionAndSlerpOrientation) {
  const auto pose = interpolate_ground_truth(two_poses(), 1002);  // a = 0.2
  ASSERT_TRUE(pose.has_value());
  EXPECT_EQ(pose->t_ns, 1002);
  EXPECT_TRUE(pose->T_world_body.translation().isApprox(Eigen::Vector3d(2, 4, -2)));
  // Slerp between yaw 0 and yaw 90 deg at 0.2: yaw 18 deg about the same axis.
  const Eigen::AngleAxisd expected(0.2 * M_PI / 2, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(pose->T_world_body.rotation().isApprox(expected.matrix(), 1e-12));
  ASSERT_TRUE(pose->velocity_m_s.has_value());
  EXPECT_TRUE(pose->velocity_m_s->isApprox(Eigen::Vector3d(1.4, 0.8, 0)));
  EXPECT_FALSE(pose->gyro_bias_rad_s.has_value());
}

TEST(InterpolateGroundTruth, ExactSamplesAndRange) {
  const auto poses = two_poses();
  EXPECT_TRUE(interpolate_ground_truth(poses, 1000)->T_world_body.isApprox(poses[0].T_world_body));
  EXPECT_TRUE(interpolate_ground_truth(poses, 1010)->T_world_body.isApprox(poses[1].T_world_body));
  EXPECT_FALSE(interpolate_ground_truth(poses, 999).has_value());
  EXPECT_FALSE(interpolate_ground_truth(poses, 1011).has_value());
  EXPECT_FALSE(interpolate_ground_truth({}, 1000).has_value());
  // A gap wider than allowed gives no pose inside it, but samples themselves still count.
  EXPECT_FALSE(interpolate_ground_truth(poses, 1005, 9).has_value());
  EXPECT_TRUE(interpolate_ground_truth(poses, 1005, 10).has_value());
  EXPECT_TRUE(interpolate_ground_truth(poses, 1010, 9).has_value());
}

TEST(InterpolateGroundTruth, PicksTheRightIntervalAmongMany) {
  std::vector<GroundTruthPose> poses;
  for (int i = 0; i < 100; ++i) poses.push_back(pose_at(i * 100, {i * 1.0, 0, 0}, 0.01 * i));
  const auto pose = interpolate_ground_truth(poses, 4275);  // between samples 42 and 43
  ASSERT_TRUE(pose.has_value());
  EXPECT_NEAR(pose->T_world_body.translation().x(), 42.75, 1e-12);
  const Eigen::AngleAxisd rotation(pose->T_world_body.rotation());
  EXPECT_NEAR(rotation.angle(), 0.4275, 1e-12);
}

TEST(InterpolateGroundTruth, TakesTheShortWayAcrossTheHalfTurn) {
  // Yaw 170 deg to yaw -170 deg: the short way passes through 180 deg, not through 0.
  const std::vector<GroundTruthPose> poses = {pose_at(0, {0, 0, 0}, 170 * M_PI / 180),
                                              pose_at(10, {0, 0, 0}, -170 * M_PI / 180)};
  const auto pose = interpolate_ground_truth(poses, 5);
  const Eigen::Matrix3d half_turn = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).matrix();
  EXPECT_TRUE(pose->T_world_body.rotation().isApprox(half_turn, 1e-12));
}

}  // namespace
}  // namespace edx::datasets
