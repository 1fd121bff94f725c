#include "workloads/backend/slam/slam_options.hpp"

#include "workloads/trace/precision_field.hpp"

namespace edx::backend::slam {

const FieldList<SlamOptions>& SlamOptions::fields() {
  using C = SlamOptions;
  static const FieldList<C> list = {
      field("window_size", &C::window_size, "", "keyframes optimized together",
            Bounds::at_least(2).at_most(100)),
      trace::precision_field(
          &C::precision,
          "arithmetic of the offloadable kernels (marginalization): fp64 or fp32 (docs/TRACE.md)"),
      field("keyframe_parallax_px", &C::keyframe_parallax_px, "px",
            "mean track parallax since the last keyframe that makes a new one", Bounds::above(0)),
      field("keyframe_tracked_ratio", &C::keyframe_tracked_ratio, "",
            "fewer frame features on landmarks than this share: a new keyframe",
            Bounds::above(0).at_most(1)),
      field("keyframe_max_interval_s", &C::keyframe_max_interval_s, "s",
            "longest time between keyframes", Bounds::above(0)),
      field("max_new_landmarks_per_keyframe", &C::max_new_landmarks_per_keyframe, "",
            "stereo features turned into landmarks per keyframe", Bounds::above(0)),
      field("min_landmark_depth_m", &C::min_landmark_depth_m, "m", "nearer landmarks are dropped",
            Bounds::above(0)),
      field("max_landmark_depth_m", &C::max_landmark_depth_m, "m",
            "farther landmarks are dropped (> min_landmark_depth_m)", Bounds::above(0)),
      field("stereo_max_depth_baselines", &C::stereo_max_depth_baselines, "",
            "stereo residuals only nearer than this many baselines (0: every point)",
            Bounds::at_least(0)),
      field("estimate_disparity_offset", &C::estimate_disparity_offset, "",
            "estimate the stereo disparity offset in every window"),
      field("disparity_offset_sigma_px", &C::disparity_offset_sigma_px, "px",
            "prior of the disparity offset", Bounds::above(0)),
      field("pixel_sigma", &C::pixel_sigma, "px", "reprojection noise", Bounds::above(0)),
      field("huber_threshold", &C::huber_threshold, "",
            "Huber threshold on the whitened reprojection error norm", Bounds::above(0)),
      field("outlier_px", &C::outlier_px, "px",
            "observations with a larger error after mapping are dropped", Bounds::above(0)),
      field("use_imu", &C::use_imu, "", "IMU factors when the dataset has an IMU"),
      field("initial_tilt_sigma_rad", &C::initial_tilt_sigma_rad, "rad",
            "prior on the first keyframe's roll and pitch", Bounds::above(0)),
      field("initial_gyro_bias_sigma", &C::initial_gyro_bias_sigma, "rad/s",
            "prior on the first keyframe's gyroscope bias", Bounds::above(0)),
      field("initial_accel_bias_sigma", &C::initial_accel_bias_sigma, "m/s^2",
            "prior on the first keyframe's accelerometer bias", Bounds::above(0)),
      field("lm_max_iterations", &C::lm_max_iterations, "", "Levenberg-Marquardt iterations",
            Bounds::at_least(1)),
      field("lm_initial_lambda", &C::lm_initial_lambda, "", "Marquardt's initial damping",
            Bounds::above(0)),
      field("lm_min_relative_decrease", &C::lm_min_relative_decrease, "",
            "a smaller relative decrease of the cost stops the iterations", Bounds::at_least(0)),
      field("tracking_iterations", &C::tracking_iterations, "",
            "iterations of the motion-only pose per frame", Bounds::at_least(1)),
      field("tracking_min_matches", &C::tracking_min_matches, "", "matches a tracked pose needs",
            Bounds::at_least(4)),
  };
  return list;
}

void SlamOptions::validate() const {
  check_fields(*this, "slam", fields());
  require_field(max_landmark_depth_m > min_landmark_depth_m, "slam", "max_landmark_depth_m",
                "a number > min_landmark_depth_m", field_value_text(max_landmark_depth_m));
}

nlohmann::json SlamOptions::to_json() const { return fields_to_json(*this, fields()); }

}  // namespace edx::backend::slam
