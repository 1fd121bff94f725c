// The geometric pieces of registration: the projection kernel's camera matrix and product
// against hand-computed values, RANSAC PnP and the motion-only refinement on synthetic 2D-3D
// correspondences with noise and outliers, and the options' checks.
#include "workloads/backend/registration/pose_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "workloads/backend/so3.hpp"

namespace edx::backend::registration {
namespace {

BackendCamera test_camera() {
  BackendCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 100;
  c.fy = 200;
  c.cx = 50;
  c.cy = 40;
  return c;
}

// R = Rz(90 deg) = [[0, -1, 0], [1, 0, 0], [0, 0, 1]], t = (1, 2, 3):
//   C = K [R | t] = [[0, -100, 50, 250], [200, 0, 40, 520], [0, 0, 1, 3]].
//   X = (1, 0, 2): R X + t = (1, 3, 5) -> Y = (350, 800, 5), (u, v) = (70, 160).
//   X = (0, 1, 0): R X + t = (0, 2, 3) -> Y = (150, 520, 3), (u, v) = (50, 173.33).
TEST(RegistrationProjection, CameraMatrixAndProductMatchHandComputedValues) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(1, 2, 3);
  const Eigen::Matrix<double, 3, 4> C = camera_matrix(test_camera(), T);
  Eigen::Matrix<double, 3, 4> expected;
  expected << 0, -100, 50, 250, 200, 0, 40, 520, 0, 0, 1, 3;
  EXPECT_LT((C - expected).cwiseAbs().maxCoeff(), 1e-12) << C;

  Eigen::Matrix4Xd X(4, 2);
  X.col(0) << 1, 0, 2, 1;
  X.col(1) << 0, 1, 0, 1;
  const Eigen::Matrix3Xd Y = project(C, X);
  Eigen::Matrix3Xd Y_expected(3, 2);
  Y_expected.col(0) << 350, 800, 5;
  Y_expected.col(1) << 150, 520, 3;
  EXPECT_LT((Y - Y_expected).cwiseAbs().maxCoeff(), 1e-12) << Y;
  EXPECT_DOUBLE_EQ(Y(0, 0) / Y(2, 0), 70);
  EXPECT_DOUBLE_EQ(Y(1, 0) / Y(2, 0), 160);
  EXPECT_NEAR(Y(1, 1) / Y(2, 1), 173.0 + 1.0 / 3.0, 1e-12);
}

// At fp32, C and X are rounded to single and the product is single's: a point 1000 m away
// (coordinates not all representable in single past 2^24 ulp) projects to within single's
// relative 2^-24 per operation of the double product, and every entry is a float.
TEST(RegistrationProjection, Fp32ProductIsSinglePrecision) {
  Eigen::Matrix<double, 3, 4> C;
  C << 0.1, -100.3, 50.7, 250.11, 200.9, 0.3, 40.1, 520.7, 0.01, 0.02, 1, 3.3;
  Eigen::Matrix4Xd X(4, 2);
  X.col(0) << 1000.123456789, -20.987654321, 2.5, 1;
  X.col(1) << 0.1, 1.2, 30.3, 1;
  const Eigen::Matrix3Xd y64 = project(C, X, trace::Precision::kFp64);
  const Eigen::Matrix3Xd y32 = project(C, X, trace::Precision::kFp32);
  EXPECT_TRUE((C * X).isApprox(y64, 0));
  for (Eigen::Index i = 0; i < y32.size(); ++i) {
    const double v = y32.data()[i];
    EXPECT_EQ(v, static_cast<double>(static_cast<float>(v)));
    const Eigen::Index row = i % 3, col = i / 3;
    const double magnitude = C.row(row).cwiseAbs() * X.col(col).cwiseAbs();
    EXPECT_LE(std::abs(v - y64.data()[i]), 8 * 0x1p-24 * magnitude);
  }
  EXPECT_NE(y32, y64);
}

/// Points in front of a camera at T_cam_world, seen with Gaussian pixel noise; the first
/// `outliers` get a pixel elsewhere in the image.
std::vector<Correspondence> synthetic_correspondences(const BackendCamera& camera,
                                                      const Eigen::Isometry3d& T_cam_world,
                                                      int count, int outliers, double noise_px,
                                                      std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::normal_distribution<double> noise(0, noise_px);
  std::vector<Correspondence> out;
  const Eigen::Isometry3d T_world_cam = T_cam_world.inverse();
  while (static_cast<int>(out.size()) < count) {
    const double z = 2 + 8 * u01(rng);
    const Eigen::Vector2d uv(camera.width * u01(rng), camera.height * u01(rng));
    const Eigen::Vector3d P((uv.x() - camera.cx) / camera.fx * z,
                            (uv.y() - camera.cy) / camera.fy * z, z);
    Correspondence c;
    c.world = T_world_cam * P;
    c.pixel = uv + Eigen::Vector2d(noise(rng), noise(rng));
    if (static_cast<int>(out.size()) < outliers) {
      c.pixel = Eigen::Vector2d(camera.width * u01(rng), camera.height * u01(rng));
    }
    c.landmark = c.feature = out.size();
    out.push_back(c);
  }
  return out;
}

Eigen::Isometry3d test_pose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = so3_exp(Eigen::Vector3d(0.1, -0.3, 0.2));
  T.translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
  return T;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return so3_log(a.linear().transpose() * b.linear()).norm() * 180 / M_PI;
}

TEST(RegistrationPnp, RansacPnpAndRefinementRecoverThePoseDespiteOutliers) {
  BackendCamera camera = test_camera();
  camera.fx = camera.fy = 400;
  camera.cx = 320;
  camera.cy = 240;
  const Eigen::Isometry3d truth = test_pose();
  const auto corr = synthetic_correspondences(camera, truth, 120, 30, 0.5, 7);
  const RegistrationOptions options;
  const PnpResult pnp = solve_pnp_ransac(camera, corr, options);
  ASSERT_TRUE(pnp.ok);
  EXPECT_LT((pnp.T_cam_world.translation() - truth.translation()).norm(), 0.05);
  EXPECT_LT(rotation_error_deg(pnp.T_cam_world, truth), 0.5);
  for (const std::size_t i : pnp.inliers) EXPECT_GE(i, 0u);
  EXPECT_GE(pnp.inliers.size(), 85u);  // the 90 true matches, up to a few at the threshold

  const RefinementResult refined = refine_pose(camera, corr, pnp.T_cam_world, options);
  EXPECT_LT((refined.T_cam_world.translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(rotation_error_deg(refined.T_cam_world, truth), 0.1);
  int outliers_kept = 0;
  for (int i = 0; i < 30; ++i) outliers_kept += refined.inlier[static_cast<std::size_t>(i)];
  EXPECT_LE(outliers_kept, 1);  // a random pixel may land within 2.4 px by chance
  EXPECT_GE(refined.inliers, 85);
  EXPECT_LT(refined.rms_px, 0.8);  // 0.5 px noise: RMS ~0.5 * sqrt(2)
  EXPECT_GT(refined.rms_px, 0.4);
}

TEST(RegistrationPnp, RefinementConvergesFromAPerturbedPoseWithoutNoise) {
  BackendCamera camera = test_camera();
  const Eigen::Isometry3d truth = test_pose();
  const auto corr = synthetic_correspondences(camera, truth, 50, 0, 0.0, 3);
  Eigen::Isometry3d start = truth;
  start.linear() = so3_exp(Eigen::Vector3d(0.02, -0.01, 0.03)) * truth.linear();
  start.translation() += Eigen::Vector3d(0.05, -0.03, 0.04);
  const RefinementResult refined = refine_pose(camera, corr, start, RegistrationOptions{});
  EXPECT_EQ(refined.inliers, 50);
  EXPECT_LT((refined.T_cam_world.translation() - truth.translation()).norm(), 1e-8);
  EXPECT_LT(rotation_error_deg(refined.T_cam_world, truth), 1e-6);
  EXPECT_LT(refined.rms_px, 1e-6);
}

TEST(RegistrationPnp, TooFewOrInconsistentCorrespondencesFail) {
  const BackendCamera camera = test_camera();
  const RegistrationOptions options;
  auto corr = synthetic_correspondences(camera, test_pose(), 3, 0, 0.0, 1);
  EXPECT_FALSE(solve_pnp_ransac(camera, corr, options).ok);
  // Every pixel random: no pose explains pnp_min_inliers of them.
  corr = synthetic_correspondences(camera, test_pose(), 40, 40, 0.0, 2);
  EXPECT_FALSE(solve_pnp_ransac(camera, corr, options).ok);
}

TEST(RegistrationOptionsTest, ValidateNamesTheBadFieldAndJsonListsAll) {
  RegistrationOptions o;
  EXPECT_NO_THROW(o.validate());
  o.min_inliers = 2;
  try {
    o.validate();
    FAIL() << "expected a throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("min_inliers"), std::string::npos) << e.what();
  }
  o = RegistrationOptions{};
  o.max_depth_m = o.min_depth_m;
  EXPECT_THROW(o.validate(), std::runtime_error);
  const nlohmann::json j = RegistrationOptions{}.to_json();
  EXPECT_EQ(j.at("min_inliers"), 20);
  EXPECT_EQ(j.at("bow_max_hamming"), 50);
  EXPECT_EQ(j.at("local_map"), true);
  EXPECT_EQ(j.at("local_map_max_keyframes"), 80);
  EXPECT_EQ(j.size(), 27u);
  o = RegistrationOptions{};
  o.local_map_neighbours = 0;
  EXPECT_THROW(o.validate(), std::runtime_error);
}

}  // namespace
}  // namespace edx::backend::registration
