#pragma once
// Rectification of a calibrated raw stereo pair with OpenCV: cv::stereoRectify with
// CALIB_ZERO_DISPARITY once, cv::initUndistortRectifyMap once per camera, cv::remap per frame.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "workloads/datasets/dataset.hpp"

namespace edx::datasets {

/// Maps raw (distorted) images of a horizontal stereo pair onto two row-aligned pinhole images
/// sharing one camera matrix. A pair that is already rectified (no distortion, equal camera
/// matrices, parallel axes, right camera on the left camera's +x axis, all to 1e-9; e.g. what
/// `edx gen` writes) is passed through untouched with its own intrinsics: no resampling.
/// Immutable after construction, so rectify_left/right are thread-safe.
class StereoRectifier {
 public:
  /// `left` and `right` carry radial-tangential distortion (k1, k2, p1, p2) and the same size;
  /// T_right_left maps raw left-camera coordinates into the raw right camera:
  /// p_right = T_right_left * p_left. `alpha` is stereoRectify's free scaling (0: valid pixels
  /// only). Throws std::runtime_error if the pair is not a left-right horizontal pair.
  StereoRectifier(const CameraIntrinsics& left, const CameraIntrinsics& right,
                  const Eigen::Isometry3d& T_right_left, double alpha);

  /// Intrinsics shared by both rectified images (no distortion, raw image size).
  const CameraIntrinsics& rectified() const { return rectified_; }
  /// Distance between the rectified optical centres: -P2(0,3) / P2(0,0).
  double baseline_m() const { return baseline_m_; }
  /// R1 and R2 of stereoRectify: p_rect_left = R_rect_left * p_raw_left (same for right).
  const Eigen::Matrix3d& R_rect_left() const { return R_rect_left_; }
  const Eigen::Matrix3d& R_rect_right() const { return R_rect_right_; }

  /// True when the pair was already rectified and images pass through unchanged.
  bool pass_through() const { return pass_through_; }

  /// Rectifies a raw image of the left / right camera (bilinear remap, constant black border).
  cv::Mat rectify_left(const cv::Mat& raw) const;
  cv::Mat rectify_right(const cv::Mat& raw) const;

 private:
  bool pass_through_ = false;
  CameraIntrinsics rectified_;
  double baseline_m_ = 0;
  Eigen::Matrix3d R_rect_left_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d R_rect_right_ = Eigen::Matrix3d::Identity();
  cv::Mat left_map_xy_, left_map_fraction_, right_map_xy_, right_map_fraction_;
};

}  // namespace edx::datasets
