#include "workloads/frontend/feature_extractor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {
namespace {

constexpr int kHalfPatch = kOrbPatchSize / 2;
constexpr int kDiscLeft = 16;   // the orientation's row loads start 16 px left of the point
constexpr int kFastBorder = 3;  // cv::FAST never reports corners within 3 px of the image edge

/// FAST with non-maximum suppression on `roi` of `level`, keypoints in the level's pixels; also
/// counts the segment-test corners before suppression into `candidates`.
std::vector<cv::KeyPoint> fast_corners(const cv::Mat& level, const cv::Rect& roi, int threshold,
                                       std::int64_t& candidates) {
  std::vector<cv::KeyPoint> corners = fast_with_suppression(level(roi), threshold, candidates);
  for (cv::KeyPoint& corner : corners) {
    corner.pt.x += static_cast<float>(roi.x);
    corner.pt.y += static_cast<float>(roi.y);
  }
  return corners;
}

/// ORB's intensity-centroid orientation (Rublee et al. 2011), as cv::ORB computes it before
/// its descriptors but does not expose: over the disc of radius 15 around the rounded point,
/// m10 = sum u I(u, v), m01 = sum v I(u, v), angle = atan2(m01, m10) in degrees [0, 360).
/// Row by row over 32 columns (u = -16..15) with the disc's weights (DiscWeights: u, and v, inside
/// the disc; 0 outside), rows v and -v together: m10 += sum u (I(u, v) + I(u, -v)), m01 += sum
/// v (I(u, v) - I(u, -v)), in 16-bit products summed in 32 bits (exact, so in any order: the
/// same moments as the pixel-by-pixel sum). Reads 16 px left of the point: the edge margin
/// (>= 19) keeps that inside the image.
float intensity_centroid_angle(const cv::Mat& image, cv::Point2f point, const DiscWeights& disc) {
  const uchar* center = &image.at<uchar>(cvRound(point.y), cvRound(point.x)) - kDiscLeft;
  const int step = static_cast<int>(image.step1());
  cv::v_int32x4 m10 = cv::v_setzero_s32(), m01 = cv::v_setzero_s32();
  for (int v = 0; v <= kHalfPatch; ++v) {
    const auto row = static_cast<std::size_t>(v);
    for (int half = 0; half < 2; ++half) {  // columns u = -16..-1, then 0..15
      cv::v_uint16x8 below_lo, below_hi, above_lo, above_hi;
      cv::v_expand(cv::v_load(center + v * step + 16 * half), below_lo, below_hi);
      cv::v_expand(cv::v_load(center - v * step + 16 * half), above_lo, above_hi);
      const std::int16_t* u_weight = disc.u[row].data() + 16 * half;
      const std::int16_t* v_weight = disc.v[row].data() + 16 * half;
      if (v == 0) {  // the centre row once: its u moment alone
        m10 += cv::v_dotprod(cv::v_reinterpret_as_s16(below_lo), cv::v_load(u_weight)) +
               cv::v_dotprod(cv::v_reinterpret_as_s16(below_hi), cv::v_load(u_weight + 8));
        continue;
      }
      m10 += cv::v_dotprod(cv::v_reinterpret_as_s16(below_lo + above_lo), cv::v_load(u_weight)) +
             cv::v_dotprod(cv::v_reinterpret_as_s16(below_hi + above_hi), cv::v_load(u_weight + 8));
      m01 += cv::v_dotprod(cv::v_reinterpret_as_s16(below_lo) - cv::v_reinterpret_as_s16(above_lo),
                           cv::v_load(v_weight)) +
             cv::v_dotprod(cv::v_reinterpret_as_s16(below_hi) - cv::v_reinterpret_as_s16(above_hi),
                           cv::v_load(v_weight + 8));
    }
  }
  return cv::fastAtan2(static_cast<float>(cv::v_reduce_sum(m01)),
                       static_cast<float>(cv::v_reduce_sum(m10)));
}

}  // namespace

namespace {

/// A pixel position of an image of size `from` on the same view resized to `to` (cv::resize's
/// pixel-centre convention): x_to = (x_from + 0.5)·W_to/W_from − 0.5, likewise in y.
cv::Point2f map_through_pixel_centres(cv::Point2f p, cv::Size from, cv::Size to) {
  const float sx = static_cast<float>(to.width) / static_cast<float>(from.width);
  const float sy = static_cast<float>(to.height) / static_cast<float>(from.height);
  return {(p.x + 0.5f) * sx - 0.5f, (p.y + 0.5f) * sy - 0.5f};
}

}  // namespace

namespace {

/// FAST-9/16's circle: the 16 pixels at distance 3 (Bresenham), in order around it.
constexpr std::array<std::array<int, 2>, 16> kFastCircle{{{0, 3},
                                                          {1, 3},
                                                          {2, 2},
                                                          {3, 1},
                                                          {3, 0},
                                                          {3, -1},
                                                          {2, -2},
                                                          {1, -3},
                                                          {0, -3},
                                                          {-1, -3},
                                                          {-2, -2},
                                                          {-3, -1},
                                                          {-3, 0},
                                                          {-3, 1},
                                                          {-2, 2},
                                                          {-1, 3}}};
constexpr int kFastArc = 9;  // contiguous circle pixels a corner needs

/// The FAST score of a segment-test corner at `p` (`circle`: the circle's byte offsets), as
/// cv::FAST ranks corners for suppression: with d_k = I(p) - I(circle_k), the highest t at which
/// p is still a corner, t = max(threshold, max over the 16 arcs A of 9 contiguous circle pixels
/// of max(min_A d, min_A -d)) - 1 (min_A -d = -max_A d). The 16 arcs' minima and maxima in two
/// 8-lane vectors each (lane i: the arc starting at circle pixel i), from d stored twice round.
int fast_score(const uchar* p, const std::array<int, 16>& circle, int threshold) {
  alignas(16) std::array<std::int16_t, 32> d{};
  for (std::size_t k = 0; k < 16; ++k) {
    d[k] = d[k + 16] = static_cast<std::int16_t>(p[0] - p[circle[k]]);
  }
  cv::v_int16x8 lo0 = cv::v_load(d.data()), hi0 = lo0;
  cv::v_int16x8 lo1 = cv::v_load(d.data() + 8), hi1 = lo1;
  for (int j = 1; j < kFastArc; ++j) {
    const cv::v_int16x8 a = cv::v_load(d.data() + j), b = cv::v_load(d.data() + 8 + j);
    lo0 = cv::v_min(lo0, a);
    hi0 = cv::v_max(hi0, a);
    lo1 = cv::v_min(lo1, b);
    hi1 = cv::v_max(hi1, b);
  }
  const cv::v_int16x8 zero = cv::v_setzero_s16();
  const cv::v_int16x8 best = cv::v_max(cv::v_max(lo0, lo1), cv::v_max(zero - hi0, zero - hi1));
  return std::max(threshold, static_cast<int>(cv::v_reduce_max(best))) - 1;
}

}  // namespace

std::vector<cv::KeyPoint> fast_with_suppression(const cv::Mat& image, int threshold,
                                                std::int64_t& candidates) {
  std::vector<cv::KeyPoint> raw;
  cv::FAST(image, raw, threshold, /*nonmaxSuppression=*/false);
  candidates += static_cast<std::int64_t>(raw.size());
  threshold = std::clamp(threshold, 0, 255);  // as cv::FAST clamps it
  std::array<int, 16> circle{};
  const int step = static_cast<int>(image.step1());
  for (std::size_t k = 0; k < 16; ++k) circle[k] = kFastCircle[k][0] + kFastCircle[k][1] * step;

  // Each corner's score, then a corner stays if its score is strictly above all 8 neighbours'
  // (0 where there is no corner; cv::FAST keeps scores in 8 bits too). The raw corners come row
  // by row, x ascending (cv::FAST's order with suppression too), so a corner's neighbours in the
  // rows above and below are found by two cursors that only move forward.
  const std::size_t n = raw.size();
  std::vector<cv::Point> at(n);
  std::vector<uchar> scores(n);
  for (std::size_t i = 0; i < n; ++i) {
    at[i] = cv::Point(static_cast<int>(raw[i].pt.x), static_cast<int>(raw[i].pt.y));
    scores[i] =
        static_cast<uchar>(fast_score(image.ptr<uchar>(at[i].y) + at[i].x, circle, threshold));
  }
  // Whether every corner of row `y`, columns x-1..x+1, scores below `s`; `cursor` is moved to the
  // first corner at or after (x - 1, y).
  const auto below_in_row = [&](std::size_t& cursor, int x, int y, uchar s) {
    const auto before = [&](std::size_t j) {
      return at[j].y < y || (at[j].y == y && at[j].x < x - 1);
    };
    while (cursor < n && before(cursor)) ++cursor;
    for (std::size_t j = cursor; j < n && at[j].y == y && at[j].x <= x + 1; ++j) {
      if (scores[j] >= s) return false;
    }
    return true;
  };
  std::vector<cv::KeyPoint> kept;
  std::size_t above = 0, same = 0, below = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const int x = at[i].x, y = at[i].y;
    const uchar s = scores[i];
    // cv::FAST compares with 0 where a neighbour has no corner: a kept score is > 0 in any case.
    bool kept_here = s > 0 && below_in_row(above, x, y - 1, s) && below_in_row(below, x, y + 1, s);
    while (same < n && (at[same].y < y || (at[same].y == y && at[same].x < x - 1))) ++same;
    for (std::size_t j = same; kept_here && j < n && at[j].y == y && at[j].x <= x + 1; ++j) {
      if (j != i && scores[j] >= s) kept_here = false;  // its own row, itself left out
    }
    if (kept_here) {
      kept.push_back(raw[i]);
      kept.back().response = static_cast<float>(s);
    }
  }
  return kept;
}

cv::Point2f ImagePyramid::to_level0(cv::Point2f p, std::size_t level) const {
  return map_through_pixel_centres(p, levels.at(level).size(), levels.front().size());
}

cv::Point2f ImagePyramid::from_level0(cv::Point2f p, std::size_t level) const {
  return map_through_pixel_centres(p, levels.front().size(), levels.at(level).size());
}

FeatureExtractor::FeatureExtractor(const FrontendOptions& options) : options_(options) {
  // Half width of the radius-15 disc per row v, made symmetric in u and v exactly as cv::ORB
  // does (its umax table), so that orientations agree with ORB's own.
  disc_row_half_width_.assign(kHalfPatch + 2, 0);
  const int vmax = cvFloor(kHalfPatch * std::sqrt(2.0) / 2 + 1);
  const int vmin = cvCeil(kHalfPatch * std::sqrt(2.0) / 2);
  for (int v = 0; v <= vmax; ++v) {
    disc_row_half_width_[static_cast<std::size_t>(v)] =
        cvRound(std::sqrt(static_cast<double>(kHalfPatch * kHalfPatch - v * v)));
  }
  for (int v = kHalfPatch, v0 = 0; v >= vmin; --v) {
    while (disc_row_half_width_[static_cast<std::size_t>(v0)] ==
           disc_row_half_width_[static_cast<std::size_t>(v0 + 1)]) {
      ++v0;
    }
    disc_row_half_width_[static_cast<std::size_t>(v)] = v0;
    ++v0;
  }
  for (int v = 0; v <= kHalfPatch; ++v) {
    const auto row = static_cast<std::size_t>(v);
    for (int u = -kDiscLeft; u < 32 - kDiscLeft; ++u) {
      const bool inside = std::abs(u) <= disc_row_half_width_[row];
      disc_.u[row][static_cast<std::size_t>(u + kDiscLeft)] =
          static_cast<std::int16_t>(inside ? u : 0);
      disc_.v[row][static_cast<std::size_t>(u + kDiscLeft)] =
          static_cast<std::int16_t>(inside ? v : 0);
    }
  }
}

ImagePyramid FeatureExtractor::build_pyramid(const cv::Mat& image) const {
  ImagePyramid pyramid;
  pyramid.levels.push_back(image);
  pyramid.scales.push_back(1.0);
  for (int level = 1; level < options_.pyramid_levels; ++level) {
    // Same size rule as cv::ORB: cvRound(W / s^l) with s^l in float.
    const float scale = static_cast<float>(std::pow(options_.scale_factor, level));
    const cv::Size size(cvRound(static_cast<float>(image.cols) / scale),
                        cvRound(static_cast<float>(image.rows) / scale));
    if (size.width < 1 || size.height < 1) break;
    cv::Mat resized;
    cv::resize(pyramid.levels.back(), resized, size, 0, 0, cv::INTER_LINEAR_EXACT);
    pyramid.levels.push_back(resized);
    pyramid.scales.push_back(scale);
  }
  return pyramid;
}

DetectedCorners FeatureExtractor::detect(const cv::Mat& image, trace::TaskRecord& fd) const {
  ScopedTaskTimer timer(fd);
  DetectedCorners out;
  out.pyramid = build_pyramid(image);
  const int margin = options_.edge_margin_px;
  const int cell = options_.grid_cell_px;
  fd.levels += static_cast<std::int64_t>(out.pyramid.levels.size());
  out.ranked.resize(out.pyramid.levels.size());

  for (std::size_t level = 0; level < out.pyramid.levels.size(); ++level) {
    const cv::Mat& img = out.pyramid.levels[level];
    const float scale = static_cast<float>(out.pyramid.scales[level]);
    const std::int64_t pixels = static_cast<std::int64_t>(img.cols) * img.rows;
    fd.pixels += pixels;
    fd.per_level.push_back({static_cast<int>(level), img.cols, img.rows, pixels, 0, 0});

    // Corners may lie in [margin, size - margin); FAST skips 3 px at the ROI edge.
    const cv::Rect area(margin, margin, img.cols - 2 * margin, img.rows - 2 * margin);
    if (area.width <= 0 || area.height <= 0) continue;
    const cv::Rect fast_roi(area.x - kFastBorder, area.y - kFastBorder,
                            area.width + 2 * kFastBorder, area.height + 2 * kFastBorder);
    std::vector<cv::KeyPoint> corners =
        fast_corners(img, fast_roi, options_.fast_threshold, fd.candidates);

    // Grid over the detection area; cells left empty are searched again with the low threshold.
    const int cols = (area.width + cell - 1) / cell, rows = (area.height + cell - 1) / cell;
    auto cell_of = [&](const cv::Point2f& p) {
      const int cx = std::min(cols - 1, (cvRound(p.x) - area.x) / cell);
      const int cy = std::min(rows - 1, (cvRound(p.y) - area.y) / cell);
      return cy * cols + cx;
    };
    std::vector<int> per_cell(static_cast<std::size_t>(cols * rows), 0);
    for (const cv::KeyPoint& c : corners) ++per_cell[static_cast<std::size_t>(cell_of(c.pt))];
    // Runs of consecutive empty cells in a grid row are searched in one call (the segment test
    // near a run's edge reads 3 px beyond it, like the full-area pass does).
    for (int cy = 0; cy < rows; ++cy) {
      for (int cx = 0; cx < cols;) {
        if (per_cell[static_cast<std::size_t>(cy * cols + cx)] > 0) {
          ++cx;
          continue;
        }
        int end = cx;
        while (end < cols && per_cell[static_cast<std::size_t>(cy * cols + end)] == 0) ++end;
        const cv::Rect run =
            cv::Rect(area.x + cx * cell, area.y + cy * cell, (end - cx) * cell, cell) & area;
        const cv::Rect retry_roi(run.x - kFastBorder, run.y - kFastBorder,
                                 run.width + 2 * kFastBorder, run.height + 2 * kFastBorder);
        for (const cv::KeyPoint& c :
             fast_corners(img, retry_roi, options_.fast_min_threshold, fd.candidates)) {
          corners.push_back(c);
        }
        cx = end;
      }
    }

    // Rank within each cell by FAST score; order all by (rank, score, y, x): every cell's best
    // corner comes before any cell's second best.
    auto by_score = [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
      if (a.response != b.response) return a.response > b.response;
      if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
      return a.pt.x < b.pt.x;
    };
    std::vector<std::vector<cv::KeyPoint>> buckets(per_cell.size());
    std::size_t deepest = 0;
    for (const cv::KeyPoint& c : corners) {
      std::vector<cv::KeyPoint>& bucket = buckets[static_cast<std::size_t>(cell_of(c.pt))];
      bucket.push_back(c);
      deepest = std::max(deepest, bucket.size());
    }
    for (std::vector<cv::KeyPoint>& bucket : buckets)
      std::sort(bucket.begin(), bucket.end(), by_score);

    std::vector<cv::KeyPoint>& ranked = out.ranked[level];
    ranked.reserve(corners.size());
    std::vector<cv::KeyPoint> round;
    for (std::size_t rank = 0; rank < deepest; ++rank) {
      round.clear();
      for (const std::vector<cv::KeyPoint>& bucket : buckets) {
        if (rank < bucket.size()) round.push_back(bucket[rank]);
      }
      std::sort(round.begin(), round.end(), by_score);
      for (cv::KeyPoint k : round) {
        k.pt = out.pyramid.to_level0(k.pt, level);
        k.octave = static_cast<int>(level);
        k.size = kOrbPatchSize * scale;
        k.angle = -1;
        ranked.push_back(k);
      }
    }
  }
  return out;
}

std::vector<cv::KeyPoint> FeatureExtractor::select(const DetectedCorners& corners,
                                                   std::span<const cv::Point2f> occupied,
                                                   int budget, int min_distance_px,
                                                   trace::TaskRecord& fd) const {
  ScopedTaskTimer timer(fd);
  std::vector<cv::KeyPoint> selected;
  if (budget <= 0 || corners.pyramid.levels.empty()) return selected;
  const cv::Mat& base = corners.pyramid.levels.front();
  const int radius = min_distance_px;

  // Free-space mask in level-0 pixels: 0 within min_feature_distance of a taken point.
  cv::Mat free_space(base.size(), CV_8U, cv::Scalar(255));
  auto occupy = [&](cv::Point2f p) {
    if (radius > 0) {
      cv::circle(free_space, cv::Point(cvRound(p.x), cvRound(p.y)), radius, cv::Scalar(0),
                 cv::FILLED);
    }
  };
  auto is_free = [&](cv::Point2f p) {
    const int x = std::clamp(cvRound(p.x), 0, base.cols - 1);
    const int y = std::clamp(cvRound(p.y), 0, base.rows - 1);
    return free_space.at<uchar>(y, x) != 0;
  };
  for (const cv::Point2f& p : occupied) occupy(p);

  // ORB's share per level: n_l = N (1 - f) / (1 - f^L) f^l with f = 1 / scale_factor.
  const std::size_t levels = corners.ranked.size();
  const double f = 1.0 / options_.scale_factor;
  std::vector<int> share(levels, 0);
  double desired = budget * (1 - f) / (1 - std::pow(f, static_cast<double>(levels)));
  int assigned = 0;
  for (std::size_t level = 0; level + 1 < levels; ++level) {
    share[level] = cvRound(desired);
    assigned += share[level];
    desired *= f;
  }
  share[levels - 1] = std::max(budget - assigned, 0);

  std::vector<std::size_t> next(levels, 0);  // next ranked corner to consider per level
  auto take_from = [&](std::size_t level, int wanted) {
    int taken = 0;
    const std::vector<cv::KeyPoint>& ranked = corners.ranked[level];
    while (taken < wanted && next[level] < ranked.size()) {
      const cv::KeyPoint& k = ranked[next[level]++];
      if (!is_free(k.pt)) continue;
      occupy(k.pt);
      selected.push_back(k);
      ++taken;
    }
    return taken;
  };
  int shortfall = 0;
  for (std::size_t level = 0; level < levels; ++level) {
    const int wanted = share[level] + shortfall;
    shortfall = wanted - take_from(level, wanted);
  }
  for (std::size_t level = 0; level < levels && shortfall > 0; ++level) {
    shortfall -= take_from(level, shortfall);
  }
  fd.keypoints += static_cast<std::int64_t>(selected.size());
  return selected;
}

ImagePyramid FeatureExtractor::smooth(const ImagePyramid& pyramid,
                                      trace::TaskRecord& if_task) const {
  ScopedTaskTimer timer(if_task);
  ImagePyramid smoothed;
  smoothed.scales = pyramid.scales;
  const int k = options_.gaussian_kernel_px;
  for (std::size_t level = 0; level < pyramid.levels.size(); ++level) {
    const cv::Mat& image = pyramid.levels[level];
    cv::Mat out;
    cv::GaussianBlur(image, out, cv::Size(k, k), options_.gaussian_sigma, options_.gaussian_sigma,
                     cv::BORDER_REFLECT_101);
    smoothed.levels.push_back(out);
    const std::int64_t pixels = static_cast<std::int64_t>(image.cols) * image.rows;
    if_task.pixels += pixels;
    if_task.levels += 1;
    if_task.per_level.push_back({static_cast<int>(level), image.cols, image.rows, pixels, 0, 0});
  }
  if_task.window_size = k;
  return smoothed;
}

bool FeatureExtractor::describable(const ImagePyramid& pyramid, cv::Point2f point,
                                   int octave) const {
  if (octave < 0 || static_cast<std::size_t>(octave) >= pyramid.levels.size()) return false;
  const cv::Mat& level = pyramid.levels[static_cast<std::size_t>(octave)];
  const cv::Point2f at_level = pyramid.from_level0(point, static_cast<std::size_t>(octave));
  const int x = cvRound(at_level.x), y = cvRound(at_level.y);
  const int margin = options_.edge_margin_px;
  return x >= margin && y >= margin && x < level.cols - margin && y < level.rows - margin;
}

cv::Mat FeatureExtractor::describe(const ImagePyramid& pyramid, const ImagePyramid& smoothed,
                                   std::vector<cv::KeyPoint>& keypoints,
                                   trace::TaskRecord& fc) const {
  cv::Mat descriptors = make_descriptors(keypoints);
  std::vector<int> levels(pyramid.levels.size());
  for (std::size_t level = 0; level < levels.size(); ++level) {
    levels[level] = static_cast<int>(level);
  }
  describe_levels(pyramid, smoothed, levels, keypoints, descriptors, fc);
  finish_description(keypoints, fc);
  return descriptors;
}

cv::Mat FeatureExtractor::make_descriptors(const std::vector<cv::KeyPoint>& keypoints) {
  return cv::Mat(static_cast<int>(keypoints.size()), 32, CV_8U, cv::Scalar(0));
}

void FeatureExtractor::finish_description(const std::vector<cv::KeyPoint>& keypoints,
                                          trace::TaskRecord& fc) const {
  std::sort(fc.per_level.begin(), fc.per_level.end(),
            [](const trace::LevelWork& a, const trace::LevelWork& b) { return a.level < b.level; });
  fc.keypoints += static_cast<std::int64_t>(keypoints.size());
  fc.descriptors += static_cast<std::int64_t>(keypoints.size());
  fc.window_size = kOrbPatchSize;
}

void FeatureExtractor::describe_levels(const ImagePyramid& pyramid, const ImagePyramid& smoothed,
                                       std::span<const int> levels,
                                       std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
                                       trace::TaskRecord& fc) const {
  ScopedTaskTimer timer(fc);
  // One single-level ORB per level: the filtered level image (IF output) is handed over with
  // the keypoints in level pixels. edgeThreshold = edge margin, so ORB's border filter keeps
  // every keypoint passed. The pixels counted are those ORB smooths again internally.
  cv::Ptr<cv::ORB> orb =
      cv::ORB::create(options_.features_per_image, 1.2f, 1, options_.edge_margin_px, 0, 2,
                      cv::ORB::HARRIS_SCORE, kOrbPatchSize, options_.fast_threshold);
  std::vector<cv::KeyPoint> at_level;
  cv::Mat level_descriptors;
  for (const int level_index : levels) {
    const auto level = static_cast<std::size_t>(level_index);
    const cv::Mat& img = pyramid.levels.at(level);
    at_level.clear();
    for (std::size_t i = 0; i < keypoints.size(); ++i) {
      if (keypoints[i].octave != level_index) continue;
      if (!describable(pyramid, keypoints[i].pt, keypoints[i].octave)) {
        throw std::logic_error("FeatureExtractor::describe: keypoint outside the edge margin");
      }
      cv::KeyPoint k = keypoints[i];
      k.pt = pyramid.from_level0(k.pt, level);
      k.octave = 0;
      k.class_id = static_cast<int>(i);
      k.angle = intensity_centroid_angle(img, k.pt, disc_);
      keypoints[i].angle = k.angle;
      at_level.push_back(k);
    }
    if (at_level.empty()) continue;
    const std::size_t handed = at_level.size();
    orb->compute(smoothed.levels.at(level), at_level, level_descriptors);
    if (at_level.size() != handed || level_descriptors.rows != static_cast<int>(handed)) {
      throw std::logic_error("FeatureExtractor::describe: cv::ORB dropped keypoints");
    }
    for (std::size_t j = 0; j < at_level.size(); ++j) {
      std::memcpy(descriptors.ptr<uchar>(at_level[j].class_id),
                  level_descriptors.ptr<uchar>(static_cast<int>(j)), 32);  // one 256-bit row
    }
    const std::int64_t pixels = static_cast<std::int64_t>(img.cols) * img.rows;
    fc.pixels += pixels;
    fc.levels += 1;
    fc.per_level.push_back({level_index, img.cols, img.rows, pixels, 0, 0});
  }
}

}  // namespace edx::frontend
