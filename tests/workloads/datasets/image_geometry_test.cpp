// Resize convention and stereo rectification checked on rendered images with known geometry.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "workloads/datasets/image_io.hpp"
#include "workloads/datasets/stereo_rectifier.hpp"

namespace edx::datasets {
namespace {

/// A float image with a Gaussian blob (sigma in px) centred at `centre`.
cv::Mat blob_image(cv::Size size, cv::Point2d centre, double sigma) {
  cv::Mat image(size, CV_32F);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const double d2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
      image.at<float>(y, x) = static_cast<float>(250.0 * std::exp(-d2 / (2 * sigma * sigma)));
    }
  }
  return image;
}

cv::Point2d centroid(const cv::Mat& image) {
  const cv::Moments m = cv::moments(image);
  return {m.m10 / m.m00, m.m01 / m.m00};
}

TEST(ResizeImage, ScaledIntrinsicsFollowTheImageContent) {
  // The principal point marks where the optical axis (0, 0, 1) lands; put a blob there.
  CameraIntrinsics camera;
  camera.width = 752;
  camera.height = 480;
  camera.fx = camera.fy = 450;
  camera.cx = 300.3;
  camera.cy = 200.7;
  const cv::Mat image = blob_image({752, 480}, {camera.cx, camera.cy}, 4.0);
  for (const cv::Size target : {cv::Size(640, 480), cv::Size(376, 240), cv::Size(1280, 720)}) {
    const CameraIntrinsics scaled = scale_intrinsics(camera, target);
    const cv::Mat resized = resize_image(image, target);
    ASSERT_EQ(resized.size(), target);
    const cv::Point2d found = centroid(resized);
    EXPECT_NEAR(found.x, scaled.cx, 0.02) << target;
    EXPECT_NEAR(found.y, scaled.cy, 0.02) << target;
    EXPECT_DOUBLE_EQ(scaled.fx, 450.0 * target.width / 752);
    EXPECT_DOUBLE_EQ(scaled.fy, 450.0 * target.height / 480);
  }
  // Resizing to the same size hands the image back untouched.
  EXPECT_EQ(resize_image(image, {752, 480}).data, image.data);
}

class RectifierOnRenderedPoints : public ::testing::Test {
 protected:
  RectifierOnRenderedPoints() {
    left_.width = right_.width = 752;
    left_.height = right_.height = 480;
    left_.fx = 458.6, left_.fy = 457.3, left_.cx = 367.2, left_.cy = 248.4;
    right_.fx = 457.6, right_.fy = 456.1, right_.cx = 380.0, right_.cy = 255.2;
    left_.distortion = {-0.283, 0.074, 0.0002, 0.00002};
    right_.distortion = {-0.284, 0.075, -0.0001, -0.00004};
    T_right_left_.linear() = (Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(-0.035, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()))
                                 .matrix();
    T_right_left_.translation() = Eigen::Vector3d(-0.110, 0.0015, 0.0008);
  }

  /// Raw (distorted) pixel of a point given in that camera's frame.
  static cv::Point2d project_raw(const CameraIntrinsics& camera, const Eigen::Vector3d& point) {
    const cv::Mat K =
        (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    std::vector<cv::Point3d> points = {{point.x(), point.y(), point.z()}};
    std::vector<cv::Point2d> pixels;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, camera.distortion, pixels);
    return pixels[0];
  }

  CameraIntrinsics left_, right_;
  Eigen::Isometry3d T_right_left_ = Eigen::Isometry3d::Identity();
};

TEST_F(RectifierOnRenderedPoints, PointsLandOnOneRowWithDisparityFocalTimesBaselineOverDepth) {
  const StereoRectifier rectifier(left_, right_, T_right_left_, 0.0);
  const CameraIntrinsics& k = rectifier.rectified();
  EXPECT_NEAR(rectifier.baseline_m(), T_right_left_.translation().norm(), 1e-12);
  for (const Eigen::Vector3d& point_left :
       {Eigen::Vector3d(0.3, -0.2, 2.0), Eigen::Vector3d(-0.8, 0.5, 3.5),
        Eigen::Vector3d(0.1, 0.35, 1.2)}) {
    // Where the point must appear in the rectified images: K_rect R1 X and K_rect R2 X_right.
    const Eigen::Vector3d rect_left = rectifier.R_rect_left() * point_left;
    const Eigen::Vector3d rect_right = rectifier.R_rect_right() * (T_right_left_ * point_left);
    const cv::Point2d expected_left(k.fx * rect_left.x() / rect_left.z() + k.cx,
                                    k.fy * rect_left.y() / rect_left.z() + k.cy);
    const cv::Point2d expected_right(k.fx * rect_right.x() / rect_right.z() + k.cx,
                                     k.fy * rect_right.y() / rect_right.z() + k.cy);
    EXPECT_NEAR(expected_left.y, expected_right.y, 1e-9);
    EXPECT_NEAR(expected_left.x - expected_right.x, k.fx * rectifier.baseline_m() / rect_left.z(),
                1e-9);
    // Render a blob at the raw distorted projections, rectify, and find it again.
    const cv::Mat raw_left = blob_image({752, 480}, project_raw(left_, point_left), 1.5);
    const cv::Mat raw_right =
        blob_image({752, 480}, project_raw(right_, T_right_left_ * point_left), 1.5);
    const cv::Point2d found_left = centroid(rectifier.rectify_left(raw_left));
    const cv::Point2d found_right = centroid(rectifier.rectify_right(raw_right));
    EXPECT_NEAR(found_left.x, expected_left.x, 0.1);
    EXPECT_NEAR(found_left.y, expected_left.y, 0.1);
    EXPECT_NEAR(found_right.x, expected_right.x, 0.1);
    EXPECT_NEAR(found_right.y, expected_right.y, 0.1);
  }
}

TEST_F(RectifierOnRenderedPoints, LargerAlphaKeepsMoreOfTheSourceWithAShorterFocalLength) {
  const StereoRectifier cropped(left_, right_, T_right_left_, 0.0);
  const StereoRectifier full(left_, right_, T_right_left_, 1.0);
  EXPECT_LT(full.rectified().fx, cropped.rectified().fx);
  EXPECT_DOUBLE_EQ(full.baseline_m(), cropped.baseline_m());
}

TEST_F(RectifierOnRenderedPoints, AlreadyRectifiedPairPassesThroughUntouched) {
  CameraIntrinsics pinhole = left_;
  pinhole.distortion = {0, 0, 0, 0};
  Eigen::Isometry3d T_right_left = Eigen::Isometry3d::Identity();
  T_right_left.translation() = Eigen::Vector3d(-0.12, 0, 0);
  const StereoRectifier rectified(pinhole, pinhole, T_right_left, 0.0);
  EXPECT_TRUE(rectified.pass_through());
  EXPECT_EQ(rectified.rectified().fx, pinhole.fx);
  EXPECT_EQ(rectified.rectified().cy, pinhole.cy);
  EXPECT_DOUBLE_EQ(rectified.baseline_m(), 0.12);
  const cv::Mat image = blob_image({752, 480}, {100, 200}, 3);
  EXPECT_EQ(rectified.rectify_left(image).data, image.data);
  // A milliradian of relative rotation is real work for the rectifier.
  T_right_left.linear() = Eigen::AngleAxisd(1e-3, Eigen::Vector3d::UnitY()).matrix();
  EXPECT_FALSE(StereoRectifier(pinhole, pinhole, T_right_left, 0.0).pass_through());
}

}  // namespace
}  // namespace edx::datasets
