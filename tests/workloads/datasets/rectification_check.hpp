#pragma once
// Row alignment of a stereo pair measured on image content: ORB features matched between the
// left and right image (mutual best Hamming match), median vertical offset of the matches.
#include <opencv2/core.hpp>

namespace edx::datasets::testing {

struct RowAlignment {
  std::size_t matches = 0;      ///< mutual best matches with a plausible disparity
  double median_abs_dy_px = 0;  ///< median |y_left - y_right| (sub-pixel corners)
};

/// Matches ORB features of `left` and `right`; keeps mutual best matches whose Hamming distance
/// is below 40 and whose disparity x_left - x_right lies in [0, max_disparity_px], refines both
/// ends with cv::cornerSubPix. The vertical offset is not used to select matches, so the median
/// is an honest figure.
RowAlignment measure_row_alignment(const cv::Mat& left, const cv::Mat& right,
                                   double max_disparity_px);

}  // namespace edx::datasets::testing
