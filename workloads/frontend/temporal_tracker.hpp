#pragma once
// Temporal matching of the left image (paper Sec. IV "Temporal Matching", Sec. V-B DC, LSS):
// pyramidal Lucas-Kanade optical flow by OpenCV, with a forward-backward check.
//
// DC builds the LK pyramid of the current left image with its Scharr derivatives
// (cv::buildOpticalFlowPyramid, withDerivatives); LSS runs cv::calcOpticalFlowPyrLK from the
// previous pyramid to the current one and back again on the prebuilt pyramids.
//
// LK iterations. OpenCV does not report how many Gauss-Newton iterations a point took. When
// count_lk_iterations is on, replay_lk() re-runs the same OpenCV solver one iteration per call
// (maxLevel 0 on each pyramid level, TermCriteria COUNT = 1, OPTFLOW_USE_INITIAL_FLOW) and
// applies OpenCV's own stopping rules between calls (|delta|^2 <= eps^2; delta cancelling the
// previous one within 0.01 px: half step back and stop; maxCount), so the counts are those of
// the timed run up to float rounding (delta is recovered as a difference of positions). The
// replay is not part of LSS's host time, nor of the frame's.
#include <opencv2/core.hpp>
#include <vector>

#include "workloads/frontend/frontend_options.hpp"
#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// An LK pyramid with derivatives as cv::buildOpticalFlowPyramid returns it:
/// [image_0, derivatives_0, image_1, derivatives_1, ...], each image padded by the window.
struct LkPyramid {
  std::vector<cv::Mat> mats;
  int max_level = -1;  ///< levels above 0 actually built (small images get fewer)
  bool empty() const { return mats.empty(); }
};

/// LK iterations of one pyramid level, summed over the points solved there.
struct LkLevelIterations {
  int level = 0;
  std::int64_t points = 0;      ///< points with at least one update at this level
  std::int64_t iterations = 0;  ///< Gauss-Newton updates computed
};

/// Result of replay_lk: per-level counts (index = level) and the final positions and status,
/// which agree with cv::calcOpticalFlowPyrLK's up to float rounding.
struct LkReplay {
  std::vector<LkLevelIterations> levels;
  std::vector<cv::Point2f> positions;
  std::vector<unsigned char> status;
};

/// How calcOpticalFlowPyrLK is called: window, top level, criteria, eigenvalue threshold
/// (no initial guesses: every point starts at its own position on the top level).
struct LkCall {
  cv::Size window{16, 16};
  int max_level = 3;
  cv::TermCriteria criteria{cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01};
  double min_eigen = 1e-4;
};

/// cv::calcOpticalFlowPyrLK on the prebuilt pyramids as `call` says; `error_out`, when given,
/// receives OpenCV's per-point residual (mean absolute grey-level difference of the window).
void run_lk(const LkPyramid& from, const LkPyramid& to, const std::vector<cv::Point2f>& points,
            const LkCall& call, std::vector<cv::Point2f>& positions,
            std::vector<unsigned char>& status, std::vector<float>* error_out = nullptr);

/// Re-runs the same LK call one iteration at a time, counting the iterations per level (see
/// the file comment).
LkReplay replay_lk(const LkPyramid& from, const LkPyramid& to,
                   const std::vector<cv::Point2f>& points, const LkCall& call);

/// Outcome of tracking points from the previous left image into the current one.
struct TrackResult {
  std::vector<cv::Point2f> positions;  ///< in the current image (level-0 px)
  std::vector<unsigned char> tracked;  ///< 1: both directions converged, round trip < threshold
  std::vector<float> round_trip_px;    ///< |backward(forward(p)) - p|, or -1 when not computed
  std::vector<float> lk_residual;      ///< forward LK's mean absolute grey-level difference, or -1
  std::vector<cv::Point2f> backward_from;  ///< points the backward pass started from
};

class TemporalTracker {
 public:
  /// `options` must be valid (FrontendOptions::validate).
  explicit TemporalTracker(const FrontendOptions& options) : options_(options) {}

  /// DC: LK pyramid of `image` with derivatives, lk_max_level levels above 0 (fewer if the
  /// image is small). Fills `dc` with pixels per level; dc.points is set by the caller.
  LkPyramid build_pyramid(const cv::Mat& image, trace::TaskRecord& dc) const;

  /// LSS: forward LK from `previous` to `current` (lk_max_level), backward LK of the converged
  /// points (lk_check_max_level), and the round-trip check (< fb_threshold_px). Fills `lss`
  /// with time, levels and point solves of both directions; count_iterations adds the
  /// iterations.
  TrackResult track(const LkPyramid& previous, const LkPyramid& current,
                    const std::vector<cv::Point2f>& points, trace::TaskRecord& lss) const;

  /// Replays both LK passes of a track() call (replay_lk) and adds per level the points solved
  /// and the iterations taken to `lss`. Measurement, not frontend work: call it outside the
  /// frame's timing.
  void count_iterations(const LkPyramid& previous, const LkPyramid& current,
                        const std::vector<cv::Point2f>& points, const TrackResult& result,
                        trace::TaskRecord& lss) const;

  /// The forward call (no initial guesses).
  LkCall forward_call() const;

 private:
  FrontendOptions options_;
};

}  // namespace edx::frontend
