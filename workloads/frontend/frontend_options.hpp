#pragma once
// Options of the stereo frontend (paper Sec. IV "Frontend", Sec. V-B tasks FD, IF, FC, MO, DR,
// DC, LSS). A plain struct with a field list; validate() names the first bad field, to_json() is
// what a trace keeps as meta.pipeline_params.
#include <nlohmann/json.hpp>

#include "common/config_fields.hpp"

namespace edx::frontend {

struct FrontendOptions {
  // --- Feature extraction: FD (pyramid, FAST, grid), IF (Gaussian), FC (oriented rBRIEF) ---
  int features_per_image = 1000;  ///< left image budget: tracked + new features
  /// Right image budget: the candidates left features are matched against. Larger than the
  /// left budget because left features are tracks that must find their corner among them.
  int right_features_per_image = 2000;
  int pyramid_levels = 4;           ///< ORB scale pyramid levels (level 0 = input image)
  double scale_factor = 1.2;        ///< size ratio of consecutive pyramid levels
  int fast_threshold = 20;          ///< FAST intensity threshold
  int fast_min_threshold = 7;       ///< retried in grid cells where fast_threshold found nothing
  int grid_cell_px = 32;            ///< grid cell side (level pixels) keypoints are spread over
  int min_feature_distance_px = 8;  ///< no two left features closer (level-0 pixels)
  int right_min_feature_distance_px = 3;  ///< right keypoints: only drops one corner found twice
  int edge_margin_px = 19;      ///< no keypoint this close to a level's border (ORB 31x31 patch)
  int gaussian_kernel_px = 7;   ///< IF kernel side, as ORB blurs before its descriptors
  double gaussian_sigma = 2.0;  ///< IF kernel sigma

  // --- Stereo matching on the rectified pair: MO (Hamming), DR (SAD block matching) ---
  int max_disparity_px = 128;  ///< search range [0, max_disparity] along the row band
  double row_band_px = 2.0;    ///< +-rows searched, scaled by the keypoint level's scale
  int hamming_threshold = 75;  ///< best distance must not exceed this (of 256 bits)
  double ratio = 0.9;          ///< best < ratio * second best (of a different corner)
  int dr_window_px = 11;       ///< SAD window side
  int dr_radius_px = 5;        ///< SAD search +-radius around the ORB match
  /// Drop refined matches whose best SAD exceeds this times the frame's median (0: keep all;
  /// ORB-SLAM uses 1.5 * 1.4 = 2.1).
  double dr_outlier_factor = 2.1;

  // --- Temporal matching: DC (LK pyramid + derivatives), LSS (pyramidal LK) ---
  /// LK window side. Even sides are centred too (samples at +-0.5, +-1.5, ...); multiples of 8
  /// run fully on OpenCV's 8-lane SIMD path (16 costs about half of 15). 12 rather than 16: a
  /// translation-only window drifts as the perspective and scale of the scene under it change,
  /// and a smaller one drifts less (the VIO's ATE falls 9-37 %, docs/VIO.md "Track window and
  /// extrinsics"); 8 drifts less still but loses KITTI's fast motion (visual SLAM drift 2.23 %
  /// against 1.88 % at 12 and 1.71 % at 16, target 2 %).
  int lk_window_px = 12;
  int lk_max_level = 3;        ///< LK pyramid levels above level 0 (forward tracking)
  int lk_check_max_level = 3;  ///< LK pyramid levels above level 0 (backward check)
  /// LK termination: iteration count per level. 5 rather than 10: the share of tracks within
  /// 1 px on the synthetic world moved by at most 0.2 points (either way), EuRoC V1_01 keeps
  /// the same tracks per frame (976), and LSS takes about a third less time.
  int lk_max_iterations = 5;
  double lk_epsilon_px = 0.03;  ///< LK termination: update length
  /// cv::calcOpticalFlowPyrLK minEigThreshold: windows whose gradient matrix has a smaller
  /// normalised minimum eigenvalue are not tracked (OpenCV default 1e-4; weak corners drift).
  double lk_min_eigen = 1e-3;
  double fb_threshold_px = 1.0;  ///< forward-backward round trip error allowed
  /// Count the LK iterations each point took per level (LSS `iterations`) by replaying the
  /// solver one iteration at a time (temporal_tracker.hpp). The replay is left out of every
  /// host time; it costs about twice LSS's own time.
  bool count_lk_iterations = true;

  // --- Execution ---
  /// Run the frontend's independent work concurrently (stereo_frontend.hpp): each stage's jobs
  /// (stage 1: DC, both detection chains, LSS in parts of the points; stage 2: FC of both images
  /// in parts of the pyramid levels) on one cv::parallel_for_ (cv::getNumThreads() threads);
  /// meanwhile OpenCV runs every other parallel_for_ of the process, the jobs' own included,
  /// serially. The recorded work is the same either way.
  bool parallel_images = true;

  /// Every option once: key, unit, accepted values and a line of doc; validate() and to_json()
  /// come from it.
  static const FieldList<FrontendOptions>& fields();
  /// Throws InputError "frontend.<key>: expected ..., got ..." for the first bad option.
  void validate() const;
};

/// Every option as a JSON object (the trace's meta.pipeline_params).
nlohmann::json to_json(const FrontendOptions& options);

}  // namespace edx::frontend
