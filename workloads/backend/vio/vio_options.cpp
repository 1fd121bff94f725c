#include "workloads/backend/vio/vio_options.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace edx::backend::vio {
namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::runtime_error(fmt::format("vio option {}: expected {}", field, expected));
}

}  // namespace

void VioOptions::validate() const {
  require(max_clones >= 3 && max_clones <= 200, "max_clones", "an integer in [3, 200]");
  require(min_track_length >= 2 && min_track_length <= max_clones, "min_track_length",
          "an integer in [2, max_clones]");
  require(update_track_length >= min_track_length, "update_track_length", ">= min_track_length");
  require(first_window_check_px >= 0, "first_window_check_px", ">= 0 (0: off)");
  require(first_window_half_px >= 3 && first_window_half_px <= 30, "first_window_half_px",
          "an integer in [3, 30]");
  require(pixel_sigma > 0, "pixel_sigma", "> 0");
  require(track_error_correlation >= 0 && track_error_correlation < 1, "track_error_correlation",
          "a value in [0, 1)");
  require(random_walk.detection_sigma_px > 0, "random_walk.detection_sigma_px", "> 0");
  require(random_walk.step_sigma_px >= 0, "random_walk.step_sigma_px", ">= 0");
  require(random_walk.step_flow_fraction >= 0, "random_walk.step_flow_fraction", ">= 0");
  require(random_walk.step_scale_px >= 0, "random_walk.step_scale_px", ">= 0");
  require(random_walk.disparity_sigma_px > 0, "random_walk.disparity_sigma_px", "> 0");
  require(min_depth_m > 0 && max_depth_m > min_depth_m, "min_depth_m/max_depth_m", "0 < min < max");
  require(max_depth_baseline_ratio >= 0, "max_depth_baseline_ratio", ">= 0 (0: no check)");
  require(max_triangulation_rms_px > 0, "max_triangulation_rms_px", "> 0");
  require(triangulation_iterations >= 1, "triangulation_iterations", ">= 1");
  require(chi2_confidence > 0 && chi2_confidence < 1, "chi2_confidence", "a value in (0, 1)");
  require(max_features_per_update >= 1, "max_features_per_update", ">= 1");
  require(max_gain_rows >= 0, "max_gain_rows", ">= 0 (0: the state's dimension)");
  require(extrinsic_rotation_sigma_rad > 0, "extrinsic_rotation_sigma_rad", "> 0");
  require(extrinsic_translation_sigma_m > 0, "extrinsic_translation_sigma_m", "> 0");
  require(gravity_m_s2 > 0, "gravity_m_s2", "> 0");
  require(imu_noise_scale > 0, "imu_noise_scale", "> 0");
  require(init_frames >= 2, "init_frames", ">= 2");
  require(static_max_accel_sd > 0, "static_max_accel_sd", "> 0");
  require(static_max_pixel_motion > 0, "static_max_pixel_motion", "> 0");
  require(init_tilt_sigma_rad > 0, "init_tilt_sigma_rad", "> 0");
  require(init_velocity_sigma_m_s > 0, "init_velocity_sigma_m_s", "> 0");
  require(!init_gyro_bias_sigma || *init_gyro_bias_sigma > 0, "init_gyro_bias_sigma",
          "> 0 (or unset)");
  require(!init_accel_bias_sigma || *init_accel_bias_sigma > 0, "init_accel_bias_sigma",
          "> 0 (or unset)");
  require(gps_lever_arm_m.allFinite(), "gps_lever_arm_m", "finite values");
  require(gps_sigma_floor_m > 0, "gps_sigma_floor_m", "> 0");
  require(gps_align_min_extent_m > 0, "gps_align_min_extent_m", "> 0");
  require(gps_align_min_fixes >= 2, "gps_align_min_fixes", ">= 2");
  require(gps_chi2_confidence > 0 && gps_chi2_confidence < 1, "gps_chi2_confidence",
          "a value in (0, 1)");
}

double VioOptions::effective_pixel_sigma() const {
  return pixel_sigma * std::sqrt((1 + track_error_correlation) / (1 - track_error_correlation));
}

nlohmann::json VioOptions::to_json() const {
  const auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json("from dataset");
  };
  return {{"max_clones", max_clones},
          {"min_track_length", min_track_length},
          {"update_track_length", update_track_length},
          {"first_window_check_px", first_window_check_px},
          {"first_window_half_px", first_window_half_px},
          {"pixel_sigma", pixel_sigma},
          {"track_error_correlation", track_error_correlation},
          {"track_noise", track_noise == TrackNoise::kWhite ? "white" : "random_walk"},
          {"random_walk",
           {{"detection_sigma_px", random_walk.detection_sigma_px},
            {"step_sigma_px", random_walk.step_sigma_px},
            {"step_flow_fraction", random_walk.step_flow_fraction},
            {"step_scale_px", random_walk.step_scale_px},
            {"disparity_sigma_px", random_walk.disparity_sigma_px}}},
          {"min_depth_m", min_depth_m},
          {"max_depth_m", max_depth_m},
          {"max_depth_baseline_ratio", max_depth_baseline_ratio},
          {"max_triangulation_rms_px", max_triangulation_rms_px},
          {"triangulation_iterations", triangulation_iterations},
          {"chi2_confidence", chi2_confidence},
          {"max_features_per_update", max_features_per_update},
          {"measurement_compression", measurement_compression},
          {"max_gain_rows", max_gain_rows},
          {"estimate_extrinsics", estimate_extrinsics},
          {"extrinsic_rotation_sigma_rad", extrinsic_rotation_sigma_rad},
          {"extrinsic_translation_sigma_m", extrinsic_translation_sigma_m},
          {"gravity_m_s2", gravity_m_s2},
          {"imu_noise_scale", imu_noise_scale},
          {"init_frames", init_frames},
          {"static_max_accel_sd", static_max_accel_sd},
          {"static_max_pixel_motion", static_max_pixel_motion},
          {"init_tilt_sigma_rad", init_tilt_sigma_rad},
          {"init_velocity_sigma_m_s", init_velocity_sigma_m_s},
          {"init_gyro_bias_sigma", optional(init_gyro_bias_sigma)},
          {"init_accel_bias_sigma", optional(init_accel_bias_sigma)},
          {"use_gps", use_gps},
          {"gps_lever_arm_m", {gps_lever_arm_m.x(), gps_lever_arm_m.y(), gps_lever_arm_m.z()}},
          {"gps_sigma_floor_m", gps_sigma_floor_m},
          {"gps_align_min_extent_m", gps_align_min_extent_m},
          {"gps_align_min_fixes", gps_align_min_fixes},
          {"gps_chi2_confidence", gps_chi2_confidence},
          {"gps_fuse_vertical", gps_fuse_vertical}};
}

}  // namespace edx::backend::vio
