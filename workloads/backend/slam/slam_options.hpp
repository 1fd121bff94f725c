#pragma once
// Options of the SLAM backend (paper Sec. IV-A, SLAM mode): keyframe selection, the sliding
// window and its Levenberg-Marquardt solver, the factor noise, and motion-only tracking.
#include <nlohmann/json.hpp>
#include <string>

namespace edx::backend::slam {

struct SlamOptions {
  // Window and keyframes.
  int window_size = 10;                  ///< keyframes optimized together (oldest marginalized)
  double keyframe_parallax_px = 10.0;    ///< mean track parallax since the last keyframe
  double keyframe_tracked_ratio = 0.6;   ///< fewer frame features on landmarks than this: new KF
  double keyframe_max_interval_s = 0.5;  ///< longest time between keyframes
  int max_new_landmarks_per_keyframe = 1000;  ///< stereo features turned into landmarks per KF
  double min_landmark_depth_m = 0.1;
  double max_landmark_depth_m = 80.0;
  /// Stereo (right-image) residuals only for points closer than this many baselines (ORB-SLAM2's
  /// close/far split): the disparity of far points is a few pixels and a sub-pixel bias of the
  /// matcher becomes a scale bias; far landmarks keep their stereo depth as the starting value
  /// and are refined from the motion parallax between keyframes. 0: stereo for every point.
  double stereo_max_depth_baselines = 40.0;

  // Factors.
  double pixel_sigma = 1.0;      ///< reprojection noise, px (left and right image)
  double huber_threshold = 2.0;  ///< Huber threshold on the whitened reprojection error norm
  double outlier_px = 4.0;       ///< observations with a larger error after mapping are dropped
  bool use_imu = true;           ///< IMU factors when the dataset has an IMU
  double initial_tilt_sigma_rad = 0.05;   ///< prior on the first keyframe's roll/pitch (IMU)
  double initial_gyro_bias_sigma = 0.01;  ///< rad/s, prior on the first keyframe's gyro bias
  double initial_accel_bias_sigma = 0.1;  ///< m/s^2, prior on the first keyframe's accel bias

  // Levenberg-Marquardt.
  int lm_max_iterations = 8;
  double lm_initial_lambda = 1e-4;  ///< Marquardt damping: H_ii <- H_ii (1 + lambda)
  double lm_min_relative_decrease = 1e-6;

  // Tracking (motion-only pose per frame against the local map).
  int tracking_iterations = 8;
  int tracking_min_matches = 12;

  /// Throws std::runtime_error naming the first bad field and the range it must lie in.
  void validate() const;
  nlohmann::json to_json() const;
};

}  // namespace edx::backend::slam
