#include "workloads/backend/vio/vio_options.hpp"

#include <cmath>

#include "workloads/trace/precision_field.hpp"

namespace edx::backend::vio {
namespace {

/// The random-walk track noise's keys (docs/VIO.md "Random-walk track noise").
const FieldList<RandomWalkTrackNoise>& random_walk_fields() {
  using C = RandomWalkTrackNoise;
  static const FieldList<C> list = {
      field("detection_sigma_px", &C::detection_sigma_px, "px", "sd: the first observation's error",
            Bounds::above(0)),
      field("step_sigma_px", &C::step_sigma_px, "px",
            "a: a step's error at no scale change or motion", Bounds::at_least(0)),
      field("step_flow_fraction", &C::step_flow_fraction, "",
            "b: a step's error per pixel of image motion", Bounds::at_least(0)),
      field("step_scale_px", &C::step_scale_px, "px", "c: a step's error per unit of scale change",
            Bounds::at_least(0)),
      field("disparity_sigma_px", &C::disparity_sigma_px, "px", "sigma_d: DR's disparity error",
            Bounds::above(0)),
  };
  return list;
}

/// An unset bias prior: the dataset's IMU file says it (else the fallback).
const Unset kFromDataset{"from dataset", "from dataset"};

}  // namespace

const FieldList<VioOptions>& VioOptions::fields() {
  using C = VioOptions;
  using Noise = VioOptions::TrackNoise;
  static const FieldList<C> list = joined<C>({
      {
          field("max_clones", &C::max_clones, "", "clones kept in the sliding window",
                Bounds::at_least(3).at_most(200)),
          trace::precision_field(&C::precision,
                                 "arithmetic of the offloadable kernels (Kalman gain, covariance "
                                 "update, GPS fusion): fp64 or fp32 (docs/TRACE.md)"),
          field("min_track_length", &C::min_track_length, "",
                "observations a track needs to be used (at most max_clones)", Bounds::at_least(2)),
          field("update_track_length", &C::update_track_length, "",
                "observations at which a live track is used and restarted (>= min_track_length)"),
          field("first_window_check_px", &C::first_window_check_px, "px",
                "first-window check: a track ends where its window lands farther (0: off)",
                Bounds::at_least(0)),
          field("first_window_half_px", &C::first_window_half_px, "px",
                "first-window check: half the window's side", Bounds::at_least(3).at_most(30)),
          field("pixel_sigma", &C::pixel_sigma, "px", "white noise of a feature coordinate",
                Bounds::above(0)),
          field("track_error_correlation", &C::track_error_correlation, "",
                "lag-1 correlation of a track's errors (inflates the update's noise)",
                Bounds::at_least(0).below(1)),
          enum_field(
              "track_noise", &C::track_noise, {"white", "random_walk"},
              [](Noise n) { return n == Noise::kWhite ? "white" : "random_walk"; },
              [](const std::string& text) {
                return text == "white" ? Noise::kWhite : Noise::kRandomWalk;
              },
              "how a track's rows are weighted in the update (docs/VIO.md \"Track noise\")"),
      },
      nested_fields("random_walk", &C::random_walk, random_walk_fields()),
      {
          field("min_depth_m", &C::min_depth_m, "m", "nearer triangulated points are rejected",
                Bounds::above(0)),
          field("max_depth_m", &C::max_depth_m, "m",
                "farther triangulated points are rejected (> min_depth_m)", Bounds::above(0)),
          field("max_depth_baseline_ratio", &C::max_depth_baseline_ratio, "",
                "most depth per camera baseline that saw the point (0: no check)",
                Bounds::at_least(0)),
          field("max_triangulation_rms_px", &C::max_triangulation_rms_px, "px",
                "RMS reprojection error after Gauss-Newton", Bounds::above(0)),
          field("triangulation_iterations", &C::triangulation_iterations, "",
                "Gauss-Newton iterations of a triangulation", Bounds::at_least(1)),
          field("chi2_confidence", &C::chi2_confidence, "",
                "chi-square gate of each feature's residual", Bounds::above(0).below(1)),
          field("max_features_per_update", &C::max_features_per_update, "",
                "most features stacked into one update", Bounds::at_least(1)),
          field("measurement_compression", &C::measurement_compression, "",
                "QR-compress the stacked H before the Kalman gain"),
          field("max_gain_rows", &C::max_gain_rows, "",
                "rows of one Kalman gain at most (0: the state's dimension)", Bounds::at_least(0)),
          field("estimate_extrinsics", &C::estimate_extrinsics, "",
                "refine the camera-IMU extrinsics online"),
          field("extrinsic_rotation_sigma_rad", &C::extrinsic_rotation_sigma_rad, "rad",
                "prior of the extrinsics' rotation", Bounds::above(0)),
          field("extrinsic_translation_sigma_m", &C::extrinsic_translation_sigma_m, "m",
                "prior of the extrinsics' translation", Bounds::above(0)),
          field("gravity_m_s2", &C::gravity_m_s2, "m/s^2", "world gravity (0, 0, -g)",
                Bounds::above(0)),
          field("imu_noise_scale", &C::imu_noise_scale, "",
                "multiplies the dataset's IMU noise densities and random walks", Bounds::above(0)),
          field("init_frames", &C::init_frames, "", "frames gathered before initializing",
                Bounds::at_least(2)),
          field("static_max_accel_sd", &C::static_max_accel_sd, "m/s^2",
                "accelerometer SD below which the IMU is still", Bounds::above(0)),
          field("static_max_pixel_motion", &C::static_max_pixel_motion, "px",
                "mean track motion below which the view is still", Bounds::above(0)),
          field("init_tilt_sigma_rad", &C::init_tilt_sigma_rad, "rad", "prior of the initial tilt",
                Bounds::above(0)),
          field("init_velocity_sigma_m_s", &C::init_velocity_sigma_m_s, "m/s",
                "prior of the initial velocity", Bounds::above(0)),
          optional_field("init_gyro_bias_sigma", &C::init_gyro_bias_sigma, "rad/s",
                         "prior of the gyroscope's bias", Bounds::above(0), kFromDataset),
          optional_field("init_accel_bias_sigma", &C::init_accel_bias_sigma, "m/s^2",
                         "prior of the accelerometer's bias", Bounds::above(0), kFromDataset),
          field("use_gps", &C::use_gps, "", "fuse GPS fixes when the dataset has them"),
          accessor_field<C>(
              "gps_lever_arm_m", FieldKind::kNumberList,
              [](const C& c) -> FieldValue {
                return std::vector<double>(c.gps_lever_arm_m.data(), c.gps_lever_arm_m.data() + 3);
              },
              [](C& c, const FieldValue& v) {
                const auto& xyz = std::get<std::vector<double>>(v);
                c.gps_lever_arm_m = Eigen::Vector3d(xyz.at(0), xyz.at(1), xyz.at(2));
              },
              "m", "the GPS antenna in the body frame (x, y, z)"),
          field("gps_sigma_floor_m", &C::gps_sigma_floor_m, "m",
                "lower bound on the fixes' stated sigma", Bounds::above(0)),
          field("gps_align_min_extent_m", &C::gps_align_min_extent_m, "m",
                "horizontal spread of fixes before aligning the frames", Bounds::above(0)),
          field("gps_align_min_fixes", &C::gps_align_min_fixes, "",
                "fixes before aligning the frames", Bounds::at_least(2)),
          field("gps_chi2_confidence", &C::gps_chi2_confidence, "", "chi-square gate of a fix",
                Bounds::above(0).below(1)),
          field("gps_fuse_vertical", &C::gps_fuse_vertical, "",
                "fuse the fixes' height (false: only their horizontal position)"),
      },
  });
  return list;
}

void VioOptions::validate() const {
  check_fields(*this, "vio", fields());
  require_field(min_track_length <= max_clones, "vio", "min_track_length",
                "an integer in [2, max_clones]", std::to_string(min_track_length));
  require_field(update_track_length >= min_track_length, "vio", "update_track_length",
                "an integer >= min_track_length", std::to_string(update_track_length));
  require_field(max_depth_m > min_depth_m, "vio", "max_depth_m", "a number > min_depth_m",
                field_value_text(max_depth_m));
}

double VioOptions::effective_pixel_sigma() const {
  return pixel_sigma * std::sqrt((1 + track_error_correlation) / (1 - track_error_correlation));
}

nlohmann::json VioOptions::to_json() const { return fields_to_json(*this, fields()); }

}  // namespace edx::backend::vio
