#include "workloads/backend/slam/slam_options.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::backend::slam {
namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::runtime_error(fmt::format("slam option {}: expected {}", field, expected));
}

}  // namespace

void SlamOptions::validate() const {
  require(window_size >= 2 && window_size <= 100, "window_size", "an integer in [2, 100]");
  require(keyframe_parallax_px > 0, "keyframe_parallax_px", "> 0");
  require(keyframe_tracked_ratio > 0 && keyframe_tracked_ratio <= 1, "keyframe_tracked_ratio",
          "a ratio in (0, 1]");
  require(keyframe_max_interval_s > 0, "keyframe_max_interval_s", "> 0");
  require(max_new_landmarks_per_keyframe > 0, "max_new_landmarks_per_keyframe", "> 0");
  require(min_landmark_depth_m > 0 && max_landmark_depth_m > min_landmark_depth_m,
          "min_landmark_depth_m/max_landmark_depth_m", "0 < min < max");
  require(stereo_max_depth_baselines >= 0, "stereo_max_depth_baselines", ">= 0");
  require(disparity_offset_sigma_px > 0, "disparity_offset_sigma_px", "> 0");
  require(pixel_sigma > 0, "pixel_sigma", "> 0");
  require(huber_threshold > 0, "huber_threshold", "> 0");
  require(outlier_px > 0, "outlier_px", "> 0");
  require(initial_tilt_sigma_rad > 0, "initial_tilt_sigma_rad", "> 0");
  require(initial_gyro_bias_sigma > 0, "initial_gyro_bias_sigma", "> 0");
  require(initial_accel_bias_sigma > 0, "initial_accel_bias_sigma", "> 0");
  require(lm_max_iterations >= 1, "lm_max_iterations", ">= 1");
  require(lm_initial_lambda > 0, "lm_initial_lambda", "> 0");
  require(lm_min_relative_decrease >= 0, "lm_min_relative_decrease", ">= 0");
  require(tracking_iterations >= 1, "tracking_iterations", ">= 1");
  require(tracking_min_matches >= 4, "tracking_min_matches", ">= 4");
}

nlohmann::json SlamOptions::to_json() const {
  return {{"window_size", window_size},
          {"keyframe_parallax_px", keyframe_parallax_px},
          {"keyframe_tracked_ratio", keyframe_tracked_ratio},
          {"keyframe_max_interval_s", keyframe_max_interval_s},
          {"max_new_landmarks_per_keyframe", max_new_landmarks_per_keyframe},
          {"min_landmark_depth_m", min_landmark_depth_m},
          {"max_landmark_depth_m", max_landmark_depth_m},
          {"stereo_max_depth_baselines", stereo_max_depth_baselines},
          {"estimate_disparity_offset", estimate_disparity_offset},
          {"disparity_offset_sigma_px", disparity_offset_sigma_px},
          {"pixel_sigma", pixel_sigma},
          {"huber_threshold", huber_threshold},
          {"outlier_px", outlier_px},
          {"use_imu", use_imu},
          {"initial_tilt_sigma_rad", initial_tilt_sigma_rad},
          {"initial_gyro_bias_sigma", initial_gyro_bias_sigma},
          {"initial_accel_bias_sigma", initial_accel_bias_sigma},
          {"lm_max_iterations", lm_max_iterations},
          {"lm_initial_lambda", lm_initial_lambda},
          {"lm_min_relative_decrease", lm_min_relative_decrease},
          {"tracking_iterations", tracking_iterations},
          {"tracking_min_matches", tracking_min_matches}};
}

}  // namespace edx::backend::slam
