#pragma once
// Options of the VIO backend (paper Sec. IV-A "Filtering" and "Fusion"): a Multi-State
// Constraint Kalman Filter (msckf_vio / OpenVINS style) with loosely coupled GPS fusion.
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>

#include "common/config_fields.hpp"
#include "workloads/backend/vio/track_noise.hpp"
#include "workloads/trace/records.hpp"

namespace edx::backend::vio {

struct VioOptions {
  // Sliding window of stochastic clones.
  int max_clones = 30;  ///< clones kept; the oldest is marginalized beyond this
  /// The arithmetic of the offloadable kernels (kalman_gain, covariance_update, and GPS fusion's
  /// gain and update): the workload's precision.
  trace::Precision precision = trace::Precision::kFp64;
  // Features.
  int min_track_length = 3;  ///< observations (frames) a track needs to be used
  /// Tracks still alive are used once they reach this many observations (then restarted), so
  /// that long tracks (slow or far scenes) inform the filter before the window is full.
  int update_track_length = 10;
  /// First-window check (docs/VIO.md "First-window check"; Shi and Tomasi 1994): each track's
  /// first window (2 first_window_half_px + 1 px square, cut where the VIO first sees the
  /// track) is aligned into every later frame under an affine warp, started at the track's
  /// position (frontend::FirstWindow); the track ends where the window's centre lands more
  /// than this far from it, or the window cannot be aligned (px; 0 turns the check off).
  /// Off by default: at 1 px it brings in the seed it was built on (12) but moves a fresh one
  /// out (23), 14 of 15 unseen seeds within 0.10 m either way, and it is host work the paper's
  /// VIO does not have (more than half the VIO backend's time).
  double first_window_check_px = 0.0;
  int first_window_half_px = 10;
  /// White measurement noise of a feature coordinate, px; the chi-square gate uses it as is (a
  /// track its residual does not fit is an outlier), the update inflates it (below).
  double pixel_sigma = 1.0;
  /// Lag-1 correlation rho of a track's position errors from frame to frame. The frontend's
  /// tracks drift slowly (measured 0.5-0.8, docs/VIO.md), so n observations carry the
  /// information of n (1 - rho) / (1 + rho) independent ones: the update uses the variance
  /// pixel_sigma^2 (1 + rho) / (1 - rho) (the variance of the mean of an AR(1) sequence).
  double track_error_correlation = 0.8;
  /// How a track's rows are weighted in the update (docs/VIO.md "Track noise"). kWhite: every
  /// coordinate independent, gated at pixel_sigma, updated at effective_pixel_sigma. kRandomWalk:
  /// each feature's rows are whitened by track_covariance(random_walk) before the null-space
  /// projection, gated at that covariance and updated at it times (1 + rho) / (1 - rho), the
  /// same inflation as kWhite's.
  /// kRandomWalk is the default: its step error follows the patch's scale change, which the
  /// EuRoC and car rigs share (docs/VIO.md "Random-walk track noise").
  enum class TrackNoise { kWhite, kRandomWalk };
  TrackNoise track_noise = TrackNoise::kRandomWalk;
  RandomWalkTrackNoise random_walk;  ///< measured against rendered depth (docs/VIO.md)
  double min_depth_m = 0.2;          ///< triangulated points nearer than this are rejected
  /// ... and farther than this (OpenVINS's max_dist, 60 m): at 0.11 m baseline a point at 60 m
  /// has 0.8 px disparity (fx 458), whose stereo depth is not determined (docs/VIO.md).
  double max_depth_m = 60.0;
  /// ... and those whose depth exceeds this many times the longest distance between the camera
  /// centres that saw them (OpenVINS's max_baseline, 40); 0: no check.
  double max_depth_baseline_ratio = 40.0;
  double max_triangulation_rms_px = 2.0;  ///< RMS reprojection error after Gauss-Newton
  int triangulation_iterations = 10;
  double chi2_confidence = 0.95;      ///< chi-square gate of each feature's residual
  int max_features_per_update = 150;  ///< most features stacked into one update
  /// QR-compress the stacked H to the state columns it touches before the Kalman gain, as
  /// msckf_vio's measurementUpdate does (Mourikis & Roumeliotis 2007, Sec. III-E). Off by
  /// default: the paper's Eq. 1 runs on the stacked, null-space-projected H, whose height then
  /// follows the number of features (issue 16). With R = sigma^2 I the update is the same
  /// either way, to round-off (docs/VIO.md "Kalman gain").
  bool measurement_compression = false;
  /// Rows of one Kalman gain at most (without compression): the accepted features are split,
  /// whole, into consecutive groups of at most this many rows (a taller feature alone), which
  /// update one after the other at the same linearization point, dx_g = K_g (r_g - H_g dx),
  /// P <- P - K_g H_g P: a sequential Kalman update, equal to the stacked one when the groups'
  /// noises are independent. One S = H P H^T + R on all of a frame's rows (219-3309 on the car
  /// mix) costs m^2 n + m^3/3: 309 ms a VIO frame at 640x360 on the 2-core host (docs/VIO.md);
  /// groups of at most n rows keep a frame within 2.7x of the 2 n^2 m of P H^T and the
  /// covariance update. 0: the state's dimension n.
  int max_gain_rows = 0;
  /// Refine the camera-IMU extrinsics online. Off by default: the datasets state calibrated
  /// extrinsics (exact for the synthetic rigs, Kalibr's for EuRoC), and on a car's planar,
  /// mostly one-axis motion their calibration is degenerate (Yang, Geneva & Huang, RA-L 2019:
  /// the translation along the rotation axis is unobservable), so the filter let them absorb
  /// the tracks' correlated errors for good (docs/VIO.md "Track window and extrinsics").
  bool estimate_extrinsics = false;
  double extrinsic_rotation_sigma_rad = 0.002;
  double extrinsic_translation_sigma_m = 0.002;
  // IMU.
  double gravity_m_s2 = 9.81;    ///< world gravity is (0, 0, -g)
  double imu_noise_scale = 1.0;  ///< multiplies the dataset's noise densities and random walks
  // Initialization.
  int init_frames = 20;                  ///< frames gathered before initializing
  double static_max_accel_sd = 0.05;     ///< m/s^2: accelerometer SD below which the IMU is still
  double static_max_pixel_motion = 0.5;  ///< px: mean track motion below which the view is still
  double init_tilt_sigma_rad = 0.02;
  double init_velocity_sigma_m_s = 0.1;
  /// Bias priors (1 sigma per axis); unset: the turn-on bias the dataset's IMU file states,
  /// else the fallbacks below.
  std::optional<double> init_gyro_bias_sigma;              ///< rad/s
  std::optional<double> init_accel_bias_sigma;             ///< m/s^2
  static constexpr double kFallbackGyroBiasSigma = 0.005;  ///< rad/s
  static constexpr double kFallbackAccelBiasSigma = 0.05;  ///< m/s^2
  // GPS fusion (loosely coupled).
  bool use_gps = true;
  Eigen::Vector3d gps_lever_arm_m = Eigen::Vector3d::Zero();  ///< antenna in the body frame
  double gps_sigma_floor_m = 0.1;        ///< lower bound on the fixes' stated sigma
  double gps_align_min_extent_m = 15.0;  ///< horizontal spread of fixes before aligning frames
  int gps_align_min_fixes = 10;
  double gps_chi2_confidence = 0.999;
  /// Fuse the fixes' height (3 rows per fix); false: only their horizontal position. Before the
  /// first turn the VIO's height is only as good as its tilt (tilt sd x distance), so on short
  /// straight runs the fixes' averaged noise moves the height by about its fused sd (worse than
  /// a lucky VIO), while on runs whose VIO height drifts they remove the drift (docs/VIO.md).
  bool gps_fuse_vertical = true;

  /// Every option once: key ("random_walk.step_sigma_px" for the nested ones), unit, accepted
  /// values and a line of doc; validate() and to_json() come from it.
  static const FieldList<VioOptions>& fields();
  /// Throws InputError "vio.<key>: expected ..., got ..." for the first bad option (the rules
  /// between options included).
  void validate() const;
  /// The update's standard deviation of a feature coordinate, px:
  /// pixel_sigma sqrt((1 + rho) / (1 - rho)).
  double effective_pixel_sigma() const;
  /// Every option (trace meta; "from dataset" for an unset bias prior).
  nlohmann::json to_json() const;
};

}  // namespace edx::backend::vio
