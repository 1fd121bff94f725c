#pragma once
// Feature extraction of one image (paper Sec. IV "Feature Extraction", Sec. V-B FD, IF, FC):
// an ORB scale pyramid, FAST corners with non-maximum suppression spread over a grid (FD), a
// Gaussian filter of the pyramid (IF) and oriented rBRIEF descriptors of the filtered pyramid
// (FC, computed by cv::ORB).
//
// Coordinates: keypoints are handed over in level-0 (input image) pixels; KeyPoint::octave is the
// pyramid level they were found on; ImagePyramid::to_level0 / from_level0 convert between a
// level's pixels and level-0 pixels (pixel centres at integers on every level).
#include <array>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <span>
#include <vector>

#include "workloads/frontend/frontend_options.hpp"
#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// Side of ORB's rBRIEF patch on a keypoint's own level (KeyPoint::size = side * level scale).
inline constexpr int kOrbPatchSize = 31;

/// ORB scale pyramid: level l is the input resized to cvRound(W / s^l) x cvRound(H / s^l)
/// (cv::resize INTER_LINEAR_EXACT from level l-1, as cv::ORB builds it).
///
/// Pixel centres are at integer coordinates on every level. cv::resize samples destination
/// pixel x at source position (x + 0.5) * (W_src / W_dst) - 0.5, and these compose, so level-l
/// pixel (x, y) sits at level-0 ((x + 0.5) W_0 / W_l - 0.5, (y + 0.5) H_0 / H_l - 0.5): the
/// ratios of the rounded sizes (which differ from s^l, and between x and y, by up to 0.2 %),
/// with the half-pixel shift. Plain x * s^l misplaces a level-3 corner by up to 1 px.
struct ImagePyramid {
  std::vector<cv::Mat> levels;
  std::vector<double> scales;  ///< s^l, the nominal level-0 pixels per level-l pixel

  /// Level-0 position of level-`level` position `p` (see above).
  cv::Point2f to_level0(cv::Point2f p, std::size_t level) const;
  /// Level-`level` position of level-0 position `p` (inverse of to_level0).
  cv::Point2f from_level0(cv::Point2f p, std::size_t level) const;
};

/// cv::FAST(image, keypoints, threshold, true) (9-of-16 segment test, then 3x3 non-maximum
/// suppression by FAST score) from one segment-test pass: cv::FAST without suppression, whose
/// corners are also the count added to `candidates`, then each corner's score (OpenCV's
/// cornerScore<16>) and the suppression as cv::FAST does them. The same keypoints (position,
/// size 7, response = score) in the same order, for about half of the segment tests. Written
/// after OpenCV 4.6's fast.cpp (Debian 12); the test EqualsCvFastWithSuppressionOnRealFrames
/// compares it with cv::FAST on real frames, so an OpenCV that scores or orders otherwise fails.
std::vector<cv::KeyPoint> fast_with_suppression(const cv::Mat& image, int threshold,
                                                std::int64_t& candidates);

/// Weights of ORB's orientation disc (radius 15) per row v = 0..15 over 32 columns
/// u = -16..15: u (the x moment's weight) and v (the y moment's) inside the disc, 0 outside.
struct DiscWeights {
  std::array<std::array<std::int16_t, 32>, 16> u{}, v{};
};

/// FD's first stage: the pyramid and, per level, the FAST corners after non-maximum
/// suppression, ordered for grid spreading (best of every cell first, then second best, ...).
struct DetectedCorners {
  ImagePyramid pyramid;
  std::vector<std::vector<cv::KeyPoint>> ranked;  ///< per level; level-0 coordinates
};

class FeatureExtractor {
 public:
  /// `options` must be valid (FrontendOptions::validate).
  explicit FeatureExtractor(const FrontendOptions& options);

  /// FD, detection: builds the pyramid, runs FAST (fast_threshold) with non-maximum
  /// suppression on every level inside the edge margin, re-runs it with fast_min_threshold in
  /// grid cells where nothing was found, and ranks corners per cell by FAST score. Adds pixels
  /// per level, candidates (segment-test corners before suppression) and time to `fd`.
  DetectedCorners detect(const cv::Mat& image, trace::TaskRecord& fd) const;

  /// FD, selection: picks up to `budget` corners spread over levels (ORB's geometric share
  /// n_l proportional to s^-l, shortfalls passed on) and grid cells, none closer than
  /// `min_distance_px` (level-0 pixels) to an `occupied` point (e.g. tracked features) or to
  /// each other. Adds the kept keypoints and time to `fd`.
  std::vector<cv::KeyPoint> select(const DetectedCorners& corners,
                                   std::span<const cv::Point2f> occupied, int budget,
                                   int min_distance_px, trace::TaskRecord& fd) const;

  /// IF: Gaussian filter (gaussian_kernel_px, gaussian_sigma; ORB's 7x7, sigma 2) of every
  /// pyramid level, the input of FC. Fills `if_task` with pixels per level.
  ImagePyramid smooth(const ImagePyramid& pyramid, trace::TaskRecord& if_task) const;

  /// FC: orientation by intensity centroid (ORB's IC angle over a radius-15 disc of the raw
  /// level, `pyramid`) and 256-bit rBRIEF descriptors by cv::ORB::compute on IF's output
  /// (`smoothed`), level by level. cv::ORB::compute cannot be told to skip its own 7x7 sigma-2
  /// smoothing of the image it is given, so the descriptors see both filters (sigma ~2.8 in
  /// all) and FC's host time includes that second pass. Sets KeyPoint::angle; returns one
  /// 32-byte row per keypoint in input order. Every keypoint must be describable().
  cv::Mat describe(const ImagePyramid& pyramid, const ImagePyramid& smoothed,
                   std::vector<cv::KeyPoint>& keypoints, trace::TaskRecord& fc) const;

  /// describe() in parts that may run concurrently: make_descriptors() the zero rows, then
  /// describe_levels() for disjoint sets of `levels` (each writes only its levels' keypoints'
  /// angles and descriptor rows, and adds its time, pixels and per_level rows to its own `fc`),
  /// then finish_description() once on the merged record (per_level by level, the counts).
  /// Identical results to describe(): each keypoint is described on its own level alone.
  static cv::Mat make_descriptors(const std::vector<cv::KeyPoint>& keypoints);
  void describe_levels(const ImagePyramid& pyramid, const ImagePyramid& smoothed,
                       std::span<const int> levels, std::vector<cv::KeyPoint>& keypoints,
                       cv::Mat& descriptors, trace::TaskRecord& fc) const;
  void finish_description(const std::vector<cv::KeyPoint>& keypoints, trace::TaskRecord& fc) const;

  /// Whether a level-0 point keeps the edge margin on pyramid level `octave`.
  bool describable(const ImagePyramid& pyramid, cv::Point2f point, int octave) const;

  /// Builds the pyramid alone (also part of detect).
  ImagePyramid build_pyramid(const cv::Mat& image) const;

 private:
  FrontendOptions options_;
  std::vector<int> disc_row_half_width_;  ///< ORB's umax: half width of the disc per row
  DiscWeights disc_;                      ///< the same disc as weights
};

}  // namespace edx::frontend
