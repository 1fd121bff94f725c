#include "tests/workloads/datasets/rectification_check.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace edx::datasets::testing {

RowAlignment measure_row_alignment(const cv::Mat& left, const cv::Mat& right,
                                   double max_disparity_px) {
  const auto orb = cv::ORB::create(1500);
  std::vector<cv::KeyPoint> left_points, right_points;
  cv::Mat left_descriptors, right_descriptors;
  orb->detectAndCompute(left, cv::noArray(), left_points, left_descriptors);
  orb->detectAndCompute(right, cv::noArray(), right_points, right_descriptors);
  RowAlignment result;
  if (left_points.empty() || right_points.empty()) return result;
  cv::BFMatcher matcher(cv::NORM_HAMMING, /*crossCheck=*/true);
  std::vector<cv::DMatch> matches;
  matcher.match(left_descriptors, right_descriptors, matches);
  // ORB positions are whole pixels of their pyramid level; refine both ends of each match to
  // sub-pixel corner positions so that the offsets are not rounded.
  std::vector<cv::Point2f> left_corners, right_corners;
  for (const auto& match : matches) {
    const cv::Point2f l = left_points[static_cast<std::size_t>(match.queryIdx)].pt;
    const cv::Point2f r = right_points[static_cast<std::size_t>(match.trainIdx)].pt;
    const double disparity = l.x - r.x;
    if (match.distance < 40 && disparity >= 0 && disparity <= max_disparity_px) {
      left_corners.push_back(l);
      right_corners.push_back(r);
    }
  }
  if (left_corners.empty()) return result;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01);
  cv::cornerSubPix(left, left_corners, cv::Size(4, 4), cv::Size(-1, -1), criteria);
  cv::cornerSubPix(right, right_corners, cv::Size(4, 4), cv::Size(-1, -1), criteria);
  std::vector<double> dy;
  for (std::size_t i = 0; i < left_corners.size(); ++i) {
    dy.push_back(std::abs(left_corners[i].y - right_corners[i].y));
  }
  result.matches = dy.size();
  if (dy.empty()) return result;
  const auto middle = dy.begin() + static_cast<std::ptrdiff_t>(dy.size() / 2);
  std::nth_element(dy.begin(), middle, dy.end());
  result.median_abs_dy_px = *middle;
  return result;
}

}  // namespace edx::datasets::testing
