#pragma once
// Stereo matching on a rectified pair (paper Sec. IV "Stereo Matching", Sec. V-B MO, DR):
// ORB descriptor matching along the epipolar row band (MO), then SAD block matching around the
// match with a parabola fit for sub-pixel disparity (DR).
#include <opencv2/core.hpp>
#include <vector>

#include "workloads/frontend/frontend_options.hpp"
#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// A left feature's stereo correspondence, or none.
struct StereoMatch {
  bool valid = false;
  int right_index = -1;  ///< matched right keypoint
  int hamming = -1;      ///< descriptor distance of the MO match
  float right_x = 0;     ///< refined right column (level-0 px); the row is the left row
  float disparity = 0;   ///< left x - right x after refinement, > 0
};

class StereoMatcher {
 public:
  /// `options` must be valid (FrontendOptions::validate).
  explicit StereoMatcher(const FrontendOptions& options) : options_(options) {}

  /// MO: for each left keypoint, the right keypoints whose row band (row_band_px scaled by
  /// their level's scale) covers the left row, whose level differs by at most one and whose
  /// disparity x_l - x_r lies in [0, max_disparity_px]; the best Hamming distance wins if it is
  /// <= hamming_threshold and < ratio x the best distance of a candidate more than 2 px away
  /// (a different corner, not the same corner found on another level). A right keypoint keeps
  /// only its closest left match. Counts comparisons and time into `mo`.
  std::vector<StereoMatch> match(const std::vector<cv::KeyPoint>& left,
                                 const cv::Mat& left_descriptors,
                                 const std::vector<cv::KeyPoint>& right,
                                 const cv::Mat& right_descriptors, trace::TaskRecord& mo) const;

  /// DR: for each valid match, SAD of a dr_window_px square window centred on the rounded
  /// left point against right windows at offsets -dr_radius..+dr_radius around the rounded
  /// match, and a parabola through the best cost and its neighbours:
  ///   offset = (c[-1] - c[+1]) / (2 (c[-1] - 2 c[0] + c[+1])),  x_r = x0 + best + offset.
  /// Matches whose best offset is at the end of the range, whose window leaves the image or
  /// whose refined disparity is not in (0, max_disparity] are dropped, and so are those whose
  /// best SAD exceeds dr_outlier_factor times the median of the frame's. `left_image` and
  /// `right_image` are the rectified images. Counts windows and time into `dr`.
  void refine(const cv::Mat& left_image, const cv::Mat& right_image,
              const std::vector<cv::KeyPoint>& left, const std::vector<cv::KeyPoint>& right,
              std::vector<StereoMatch>& matches, trace::TaskRecord& dr) const;

 private:
  FrontendOptions options_;
};

}  // namespace edx::frontend
