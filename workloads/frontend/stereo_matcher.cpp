#include "workloads/frontend/stereo_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <opencv2/core/hal/hal.hpp>

#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {
namespace {

/// Candidates closer than this (px) to the best one count as the same corner found on another
/// pyramid level, not as a rival for the ratio test.
constexpr float kSameCornerPx = 2.0f;
constexpr int kDescriptorBytes = 32;

}  // namespace

std::vector<StereoMatch> StereoMatcher::match(const std::vector<cv::KeyPoint>& left,
                                              const cv::Mat& left_descriptors,
                                              const std::vector<cv::KeyPoint>& right,
                                              const cv::Mat& right_descriptors,
                                              trace::TaskRecord& mo) const {
  ScopedTaskTimer timer(mo);
  std::vector<StereoMatch> matches(left.size());
  mo.keypoints += static_cast<std::int64_t>(left.size());
  if (left.empty() || right.empty()) return matches;

  auto level_scale = [&](int octave) { return std::pow(options_.scale_factor, octave); };
  // Right keypoints bucketed by every row their band covers.
  float max_row = 0;
  for (const cv::KeyPoint& k : left) max_row = std::max(max_row, k.pt.y);
  for (const cv::KeyPoint& k : right) max_row = std::max(max_row, k.pt.y);
  std::vector<float> band(right.size());
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(max_row) + 2);
  for (std::size_t j = 0; j < right.size(); ++j) {
    band[j] = static_cast<float>(options_.row_band_px * level_scale(right[j].octave));
    const int first = std::max(0, static_cast<int>(std::floor(right[j].pt.y - band[j])));
    const int last = std::min(static_cast<int>(rows.size()) - 1,
                              static_cast<int>(std::ceil(right[j].pt.y + band[j])));
    for (int r = first; r <= last; ++r)
      rows[static_cast<std::size_t>(r)].push_back(static_cast<int>(j));
  }

  const float max_disparity = static_cast<float>(options_.max_disparity_px);
  std::vector<int> owner(right.size(), -1);  // left index holding each right keypoint
  struct Candidate {
    int index;
    int distance;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < left.size(); ++i) {
    const cv::KeyPoint& l = left[i];
    const std::vector<int>& bucket = rows[static_cast<std::size_t>(cvRound(l.pt.y))];
    candidates.clear();
    const uchar* descriptor = left_descriptors.ptr<uchar>(static_cast<int>(i));
    for (const int j : bucket) {
      const cv::KeyPoint& r = right[static_cast<std::size_t>(j)];
      if (std::abs(r.octave - l.octave) > 1) continue;
      if (std::abs(r.pt.y - l.pt.y) > band[static_cast<std::size_t>(j)]) continue;
      const float disparity = l.pt.x - r.pt.x;
      if (disparity < 0 || disparity > max_disparity) continue;
      const int distance =
          cv::hal::normHamming(descriptor, right_descriptors.ptr<uchar>(j), kDescriptorBytes);
      ++mo.comparisons;
      candidates.push_back({j, distance});
    }
    if (candidates.empty()) continue;
    const Candidate best = *std::min_element(
        candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
          return a.distance != b.distance ? a.distance < b.distance : a.index < b.index;
        });
    if (best.distance > options_.hamming_threshold) continue;
    const float best_x = right[static_cast<std::size_t>(best.index)].pt.x;
    int second = 257;
    for (const Candidate& c : candidates) {
      if (std::abs(right[static_cast<std::size_t>(c.index)].pt.x - best_x) > kSameCornerPx) {
        second = std::min(second, c.distance);
      }
    }
    if (second <= 256 && !(best.distance < options_.ratio * second)) continue;

    // One left feature per right keypoint: the closer descriptor keeps it.
    int& holder = owner[static_cast<std::size_t>(best.index)];
    if (holder >= 0) {
      StereoMatch& other = matches[static_cast<std::size_t>(holder)];
      if (other.hamming <= best.distance) continue;
      other = StereoMatch{};
    }
    holder = static_cast<int>(i);
    StereoMatch& m = matches[i];
    m.valid = true;
    m.right_index = best.index;
    m.hamming = best.distance;
    m.right_x = best_x;
    m.disparity = l.pt.x - best_x;
  }
  return matches;
}

void StereoMatcher::refine(const cv::Mat& left_image, const cv::Mat& right_image,
                           const std::vector<cv::KeyPoint>& left,
                           const std::vector<cv::KeyPoint>& right,
                           std::vector<StereoMatch>& matches, trace::TaskRecord& dr) const {
  ScopedTaskTimer timer(dr);
  const int half = options_.dr_window_px / 2;
  const int radius = options_.dr_radius_px;
  const int offsets = 2 * radius + 1;
  dr.window_size = options_.dr_window_px;
  dr.search_range = offsets;
  std::vector<int> cost(static_cast<std::size_t>(offsets));
  std::vector<int> best_cost(matches.size(), 0);
  for (std::size_t i = 0; i < matches.size(); ++i) {
    StereoMatch& m = matches[i];
    if (!m.valid) continue;
    ++dr.keypoints;
    const int xl = cvRound(left[i].pt.x), y = cvRound(left[i].pt.y);
    const int xr = cvRound(right[static_cast<std::size_t>(m.right_index)].pt.x);
    if (y - half < 0 || y + half >= left_image.rows || xl - half < 0 ||
        xl + half >= left_image.cols || xr - radius - half < 0 ||
        xr + radius + half >= right_image.cols) {
      m = StereoMatch{};
      continue;
    }
    // cost[k] = sum over the window of |L(xl + u, y + v) - R(xr + k - radius + u, y + v)|.
    std::fill(cost.begin(), cost.end(), 0);
    for (int v = -half; v <= half; ++v) {
      const uchar* l_row = left_image.ptr<uchar>(y + v) + xl;
      const uchar* r_row = right_image.ptr<uchar>(y + v) + xr;
      for (int k = 0; k < offsets; ++k) {
        const uchar* r_window = r_row + (k - radius);
        int sum = 0;
        for (int u = -half; u <= half; ++u) sum += std::abs(l_row[u] - r_window[u]);
        cost[static_cast<std::size_t>(k)] += sum;
      }
    }
    ++dr.windows;
    const int best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
    if (best == 0 || best == offsets - 1) {  // minimum at the end of the range: no parabola
      m = StereoMatch{};
      continue;
    }
    const double before = cost[static_cast<std::size_t>(best - 1)];
    const double at = cost[static_cast<std::size_t>(best)];
    const double after = cost[static_cast<std::size_t>(best + 1)];
    const double curvature = before - 2 * at + after;
    const double offset = curvature > 0 ? (before - after) / (2 * curvature) : 0.0;
    const double right_x = xr + (best - radius) + offset;
    const double disparity = xl - right_x;  // at the window centre, the rounded left column
    if (!(disparity > 0) || disparity > options_.max_disparity_px) {
      m = StereoMatch{};
      continue;
    }
    m.disparity = static_cast<float>(disparity);
    m.right_x = left[i].pt.x - m.disparity;
    best_cost[i] = static_cast<int>(at);
  }

  // Outliers: a best SAD far above the frame's median means the windows do not agree (an
  // occlusion boundary, a wrong descriptor match): cost > dr_outlier_factor * median.
  if (options_.dr_outlier_factor <= 0) return;
  std::vector<int> costs;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i].valid) costs.push_back(best_cost[i]);
  }
  if (costs.empty()) return;
  const auto middle = costs.begin() + static_cast<std::ptrdiff_t>(costs.size() / 2);
  std::nth_element(costs.begin(), middle, costs.end());
  const double limit = options_.dr_outlier_factor * *middle;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (matches[i].valid && best_cost[i] > limit) matches[i] = StereoMatch{};
  }
}

}  // namespace edx::frontend
