// RANSAC PnP (workloads/backend/pnp_ransac.hpp): a known pose recovered from exact
// correspondences, in pixels and in normalized coordinates, with outliers among them; a solver
// failure (too few points, mismatched counts) is no pose, and no input throws.
#include "workloads/backend/pnp_ransac.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace edx::backend {
namespace {

struct Scene {
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> object;
  std::vector<Eigen::Vector2d> image;
};

/// 60 points in a box 4-8 m in front of the camera, seen through `K` at a known pose; every
/// tenth image point moved 40 units away (an outlier).
Scene scene(const PnpIntrinsics& K, double outlier_offset) {
  Scene s;
  s.T_cam_object.linear() =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
  s.T_cam_object.translation() = Eigen::Vector3d(0.4, -0.2, 0.3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lateral(-2, 2), depth(4, 8);
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d X(lateral(rng), lateral(rng), depth(rng));
    const Eigen::Vector3d P = s.T_cam_object * X;
    Eigen::Vector2d x(K.fx * P.x() / P.z() + K.cx, K.fy * P.y() / P.z() + K.cy);
    if (i % 10 == 0) x.x() += outlier_offset;
    s.object.push_back(X);
    s.image.push_back(x);
  }
  return s;
}

void expect_pose(const Eigen::Isometry3d& expected, const Eigen::Isometry3d& actual) {
  EXPECT_LT((expected.linear() - actual.linear()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((expected.translation() - actual.translation()).norm(), 1e-6);
}

TEST(PnpRansac, RecoversThePoseInPixelsWithOutliersLeftOut) {
  const PnpIntrinsics K{400, 410, 320, 240};
  const Scene s = scene(K, 40);
  const auto solution = pnp_ransac(s.object, s.image, K,
                                   {.iterations = 100,
                                    .reprojection_threshold = 2,
                                    .confidence = 0.99,
                                    .method = PnpMethod::kEpnp});
  ASSERT_TRUE(solution);
  expect_pose(s.T_cam_object, solution->T_cam_object);
  EXPECT_EQ(solution->inliers.size(), 54u);
  for (const int i : solution->inliers) EXPECT_NE(i % 10, 0) << i;
}

TEST(PnpRansac, RecoversThePoseInNormalizedCoordinates) {
  const Scene s = scene(PnpIntrinsics{}, 0.1);
  const auto solution = pnp_ransac(s.object, s.image, PnpIntrinsics{},
                                   {.iterations = 200,
                                    .reprojection_threshold = 2.0 / 400,
                                    .confidence = 0.99,
                                    .method = PnpMethod::kIterative});
  ASSERT_TRUE(solution);
  expect_pose(s.T_cam_object, solution->T_cam_object);
  EXPECT_EQ(solution->inliers.size(), 54u);
}

TEST(PnpRansac, ASolverFailureIsNoPoseNotAnException) {
  const PnpIntrinsics K{400, 400, 320, 240};
  const PnpRansacSettings settings{.iterations = 100,
                                   .reprojection_threshold = 2,
                                   .confidence = 0.99,
                                   .method = PnpMethod::kEpnp};
  const Scene s = scene(K, 0);
  // Three points: OpenCV asserts at least four (cv::Exception).
  const std::vector<Eigen::Vector3d> three(s.object.begin(), s.object.begin() + 3);
  const std::vector<Eigen::Vector2d> three_px(s.image.begin(), s.image.begin() + 3);
  EXPECT_FALSE(pnp_ransac(three, three_px, K, settings));
  // Mismatched sizes: OpenCV asserts equal counts.
  EXPECT_FALSE(pnp_ransac(s.object, three_px, K, settings));
  // Points on one line seen at one pixel (degenerate): a pose or none, never an exception.
  std::vector<Eigen::Vector3d> line;
  std::vector<Eigen::Vector2d> one_point;
  for (int i = 0; i < 20; ++i) {
    line.emplace_back(0, 0, 4 + i);
    one_point.emplace_back(320, 240);
  }
  EXPECT_NO_THROW(pnp_ransac(line, one_point, K, settings));
}

}  // namespace
}  // namespace edx::backend
