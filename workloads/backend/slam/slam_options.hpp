#pragma once
// Options of the SLAM backend (paper Sec. IV-A, SLAM mode): keyframe selection, the sliding
// window and its Levenberg-Marquardt solver, the factor noise, and motion-only tracking.
#include <nlohmann/json.hpp>
#include <string>

#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend::slam {

struct SlamOptions {
  // Window and keyframes.
  int window_size = 10;  ///< keyframes optimized together (oldest marginalized)
  /// The arithmetic of the offloadable kernel (marginalization): the workload's precision.
  trace::Precision precision = trace::Precision::kFp64;
  double keyframe_parallax_px = 10.0;    ///< mean track parallax since the last keyframe
  double keyframe_tracked_ratio = 0.6;   ///< fewer frame features on landmarks than this: new KF
  double keyframe_max_interval_s = 0.5;  ///< longest time between keyframes
  int max_new_landmarks_per_keyframe = 1000;  ///< stereo features turned into landmarks per KF
  double min_landmark_depth_m = 0.1;
  double max_landmark_depth_m = 80.0;
  /// Stereo (right-image) residuals only for points closer than this many baselines (ORB-SLAM2's
  /// close/far split, 40 there); 0: stereo for every point (default). With the disparity offset
  /// estimated, far points are what makes it observable (their depth error delta / d is the
  /// largest); with only close points it trades against the scale (docs/SLAM.md, KITTI).
  double stereo_max_depth_baselines = 0.0;

  /// Stereo disparity offset: the right image's x is modelled as pi_x(P - b e_x) + delta, i.e.
  /// a measured disparity d = d_true - delta (a rectification error of the right principal
  /// point, which makes depth errors grow as delta / d with distance). When estimated, delta is
  /// one more unknown of every window LM, observable because left-image parallax across
  /// keyframes fixes relative depths independently of it (near and far points disagree on the
  /// scale unless delta is right); a zero-mean prior with disparity_offset_sigma_px keeps it
  /// bounded when the window does not see enough depth range. Marginalization conditions on it.
  bool estimate_disparity_offset = true;
  double disparity_offset_sigma_px = 2.0;

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

  /// Every option once: key, unit, accepted values and a line of doc; validate() and to_json()
  /// come from it.
  static const FieldList<SlamOptions>& fields();
  /// Throws InputError "slam.<key>: expected ..., got ..." for the first bad option.
  void validate() const;
  nlohmann::json to_json() const;
};

}  // namespace edx::backend::slam
