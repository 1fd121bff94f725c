#pragma once
// The stereo visual frontend shared by every backend mode (paper Sec. IV, Fig. "algo"): per
// rectified stereo frame it extracts features on both images, tracks the previous frame's
// features into the left image, fills the budget with new features where tracks are missing,
// matches the left features into the right image, and records every task it ran with its host
// time and work counts (docs/TRACE.md, tasks table).
//
// Per frame, in this order (when parallel_images is on, stages 1 and 2 each run as jobs on
// OpenCV's thread pool: stage 1 as DC(L), the two detection chains and LSS(L) in parts of the
// points after DC; stage 2, after FD(L)'s selection, as FC of each image in parts of its
// pyramid levels; the task rows record the same work as one after another):
//   stage 1, chain 1: DC(L) LK pyramid of the left image, LSS(L) tracking the previous left
//                     features
//            chain 2: FD(L) detection, IF(L) of the left pyramid
//            chain 3: FD(R) detection + selection, IF(R) of the right pyramid
//   stage 2, chain 1: FD(L) selection of new features away from the tracks, FC(L) on tracks +
//                     new features
//            chain 2: FC(R)
//   then:    MO and DR (left features against right keypoints)
// LK (DC, LSS) and SAD block matching (DR) read the images themselves, not IF's output: on the
// synthetic world both are more accurate unfiltered (the paper has DR read the raw image too),
// and LK's eigenvalue test keeps more tracks on EuRoC.
// Task rows are emitted in the order FD L, IF L, FD R, IF R, DC L, LSS L, FC L, FC R, MO LR,
// DR LR (ten per frame; on the first frame LSS has no points). What their counts mean:
//   FD   pixels, per_level: the ORB pyramid (all levels); candidates: FAST segment-test corners
//        before non-maximum suppression, both thresholds; keypoints: kept (left: new features
//        only, tracks are LSS's; right: all). host_ns includes building the pyramid.
//   IF   pixels, per_level: the pyramid levels filtered; window_size: Gaussian kernel side.
//   FC   keypoints = descriptors: described (left: tracks + new); window_size: 31 (patch);
//        pixels, per_level: levels cv::ORB::compute smoothed again internally (see
//        FeatureExtractor::describe); host_ns includes orientation and that second filter.
//   MO   keypoints: left features matched; comparisons: Hamming distances computed.
//   DR   keypoints: MO matches handed over; windows: those refined (window inside the image);
//        window_size: 11; search_range: 11 offsets (+-5 px).
//   DC   pixels, per_level: LK pyramid levels (derivatives of each); window_size: 3 (Scharr);
//        points: previous features to be tracked.
//   LSS  points: point solves, forward (every previous feature) plus backward (the converged
//        ones); per_level points: solves with at least one update on that level; iterations:
//        Gauss-Newton updates counted by replaying OpenCV's solver (temporal_tracker.hpp), 0
//        when count_lk_iterations is off; window_size: LK window side.
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "workloads/frontend/feature_extractor.hpp"
#include "workloads/frontend/frontend_options.hpp"
#include "workloads/frontend/stereo_matcher.hpp"
#include "workloads/frontend/temporal_tracker.hpp"
#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// Geometry of the rectified pair the frontend needs for depth.
struct StereoCamera {
  double fx = 0;          ///< rectified focal length, px (at the processed resolution)
  double baseline_m = 0;  ///< distance between the rectified optical centres
};

/// One feature of the left image, what the backends consume.
struct Feature {
  std::int64_t id = 0;  ///< track id, unique within a run; kept while LK tracks the feature
  int age = 0;          ///< frames the track has existed before this one (0: detected now)
  int octave = 0;       ///< pyramid level it was detected on (descriptor scale)
  cv::Point2f left;     ///< rectified left image, level-0 px
  float angle = 0;      ///< ORB orientation, degrees
  float response = 0;   ///< FAST score at detection
  std::array<std::uint8_t, 32> descriptor{};  ///< rBRIEF at the current position
  bool stereo = false;  ///< matched in the right image (the fields below are valid)
  cv::Point2f right;    ///< rectified right image (same row as left)
  float disparity = 0;  ///< left.x - right.x, px, > 0
  double depth_m = 0;   ///< fx * baseline / disparity
  int hamming = -1;     ///< descriptor distance of the stereo match
  /// Of the temporal match that brought a tracked feature here (-1 for a new one), for
  /// diagnostics: LK's residual (OpenCV's `err`, the window's mean absolute grey-level
  /// difference after convergence) and the forward-backward round trip, px.
  float lk_residual = -1;
  float round_trip_px = -1;
};

/// Counts of one frame (also found in the task rows).
struct FrameStats {
  int left_keypoints = 0;   ///< features of the left image (tracked + new)
  int right_keypoints = 0;  ///< keypoints of the right image
  int tracked = 0;          ///< previous features tracked into this frame
  int lost = 0;             ///< previous features not tracked (LK failed, round trip, border)
  int new_features = 0;     ///< features detected in this frame
  int stereo_matches = 0;   ///< left features with a refined stereo match
};

/// What the frontend produced for one stereo frame.
struct FrontendFrame {
  std::size_t index = 0;                 ///< frames processed before this one
  std::vector<Feature> features;         ///< tracked features first (by id), then new ones
  std::vector<trace::TaskRecord> tasks;  ///< the ten task rows, see the file comment
  /// CPU time of process()'s work without the LK iteration replay: the calling thread's, plus
  /// with parallel_images each concurrent chain's own (not the pool's waiting), docs/TRACE.md
  std::int64_t host_ns = 0;
  /// host_ns with each set of concurrent jobs counted by its span, the largest CPU time one
  /// worker spent on its jobs: the frame's time on cv::getNumThreads() otherwise idle cores
  /// (waits between jobs left out), what a wall clock shows when no other process competes.
  /// host_ns without parallel_images.
  std::int64_t span_ns = 0;
  FrameStats stats;
};

class StereoFrontend {
 public:
  /// Throws std::runtime_error on invalid options or camera (fx, baseline not > 0).
  StereoFrontend(const FrontendOptions& options, const StereoCamera& camera);

  /// Processes the next rectified pair (8-bit grayscale, same size, the size of the first
  /// pair, at least 64x64). Throws std::runtime_error naming the frame and what is wrong.
  FrontendFrame process(const cv::Mat& left, const cv::Mat& right);

  /// Forgets the previous frame and its tracks (ids keep counting up).
  void reset();

  const FrontendOptions& options() const { return options_; }
  const StereoCamera& camera() const { return camera_; }

 private:
  struct Track {
    std::int64_t id = 0;
    int age = 0;
    int octave = 0;
    float response = 0;
  };

  FrontendOptions options_;
  StereoCamera camera_;
  FeatureExtractor extractor_;
  StereoMatcher matcher_;
  TemporalTracker tracker_;

  std::size_t frames_ = 0;
  std::optional<cv::Size> image_size_;
  std::int64_t next_id_ = 0;
  LkPyramid previous_pyramid_;
  std::vector<cv::Point2f> previous_points_;
  std::vector<Track> previous_tracks_;
};

}  // namespace edx::frontend
