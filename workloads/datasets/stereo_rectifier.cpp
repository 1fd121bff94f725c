#include "workloads/datasets/stereo_rectifier.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace edx::datasets {
namespace {

cv::Mat camera_matrix(const CameraIntrinsics& c) {
  return (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
}

cv::Mat distortion_vector(const CameraIntrinsics& c) {
  cv::Mat d = cv::Mat::zeros(1, 4, CV_64F);
  for (std::size_t i = 0; i < c.distortion.size() && i < 4; ++i) {
    d.at<double>(0, static_cast<int>(i)) = c.distortion[i];
  }
  return d;
}

bool all_zero(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return v == 0; });
}

/// Already rectified: no distortion, one camera matrix, parallel axes and the right camera on
/// the +x axis of the left one (p_right = p_left - (B, 0, 0)), all to 1e-9.
bool is_rectified_pair(const CameraIntrinsics& left, const CameraIntrinsics& right,
                       const Eigen::Isometry3d& T_right_left) {
  const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(a); };
  const Eigen::Vector3d t = T_right_left.translation();
  return all_zero(left.distortion) && all_zero(right.distortion) && same(left.fx, right.fx) &&
         same(left.fy, right.fy) && same(left.cx, right.cx) && same(left.cy, right.cy) &&
         T_right_left.rotation().isApprox(Eigen::Matrix3d::Identity(), 1e-9) && t.x() < 0 &&
         std::abs(t.y()) <= 1e-9 * std::abs(t.x()) && std::abs(t.z()) <= 1e-9 * std::abs(t.x());
}

}  // namespace

StereoRectifier::StereoRectifier(const CameraIntrinsics& left, const CameraIntrinsics& right,
                                 const Eigen::Isometry3d& T_right_left, double alpha) {
  if (left.width != right.width || left.height != right.height) {
    throw std::runtime_error(fmt::format("stereo cameras differ in resolution: {}x{} vs {}x{}",
                                         left.width, left.height, right.width, right.height));
  }
  const cv::Size size(left.width, left.height);
  if (is_rectified_pair(left, right, T_right_left)) {
    // Nothing to undo: hand the images over as they are, with the stated intrinsics.
    pass_through_ = true;
    rectified_ = left;
    rectified_.distortion.clear();
    baseline_m_ = -T_right_left.translation().x();
    return;
  }
  const cv::Mat K_left = camera_matrix(left), K_right = camera_matrix(right);
  const cv::Mat D_left = distortion_vector(left), D_right = distortion_vector(right);
  cv::Mat R, T;
  const Eigen::Matrix3d rotation = T_right_left.rotation();
  const Eigen::Vector3d translation = T_right_left.translation();
  cv::eigen2cv(rotation, R);
  cv::eigen2cv(translation, T);

  cv::Mat R1, R2, P1, P2, Q;
  try {
    cv::stereoRectify(K_left, D_left, K_right, D_right, size, R, T, R1, R2, P1, P2, Q,
                      cv::CALIB_ZERO_DISPARITY, alpha, size);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(fmt::format("stereo rectification failed: {}", e.what()));
  }

  // Horizontal pair: P2 = [f 0 cx -f*B; 0 f cy 0; 0 0 1 0] with B > 0 (right camera on the +x
  // side of the left one). A vertical pair would put the offset in P2(1,3) instead.
  const double f = P1.at<double>(0, 0);
  baseline_m_ = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  if (std::abs(P2.at<double>(1, 3)) > 1e-9 * std::abs(P2.at<double>(0, 3)) + 1e-12 ||
      !(baseline_m_ > 0)) {
    throw std::runtime_error(
        "stereo pair is not horizontal with the right camera on the +x side of the left one");
  }
  rectified_.width = size.width;
  rectified_.height = size.height;
  rectified_.fx = f;
  rectified_.fy = P1.at<double>(1, 1);
  rectified_.cx = P1.at<double>(0, 2);
  rectified_.cy = P1.at<double>(1, 2);
  cv::cv2eigen(R1, R_rect_left_);
  cv::cv2eigen(R2, R_rect_right_);

  // Fixed-point maps (CV_16SC2 + CV_16UC1) remap about twice as fast as float maps.
  cv::initUndistortRectifyMap(K_left, D_left, R1, P1, size, CV_16SC2, left_map_xy_,
                              left_map_fraction_);
  cv::initUndistortRectifyMap(K_right, D_right, R2, P2, size, CV_16SC2, right_map_xy_,
                              right_map_fraction_);
}

cv::Mat StereoRectifier::rectify_left(const cv::Mat& raw) const {
  if (pass_through_) return raw;
  cv::Mat rectified;
  cv::remap(raw, rectified, left_map_xy_, left_map_fraction_, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(0));
  return rectified;
}

cv::Mat StereoRectifier::rectify_right(const cv::Mat& raw) const {
  if (pass_through_) return raw;
  cv::Mat rectified;
  cv::remap(raw, rectified, right_map_xy_, right_map_fraction_, cv::INTER_LINEAR,
            cv::BORDER_CONSTANT, cv::Scalar(0));
  return rectified;
}

}  // namespace edx::datasets
