// Stereo matching (MO, DR) on planes whose disparity is known in closed form.
#include "workloads/frontend/stereo_matcher.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/features2d.hpp>

#include "tests/workloads/frontend/plane_scene.hpp"
#include "workloads/frontend/feature_extractor.hpp"

namespace edx::frontend {
namespace {

using trace::Image;
using trace::Task;

struct Extracted {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  cv::Mat image;
};

Extracted extract(const FeatureExtractor& extractor, const cv::Mat& image, int budget,
                  int min_distance_px) {
  trace::TaskRecord fd, filter, fc;
  const DetectedCorners corners = extractor.detect(image, fd);
  Extracted out;
  out.keypoints = extractor.select(corners, {}, budget, min_distance_px, fd);
  out.image = image;
  out.descriptors = extractor.describe(corners.pyramid, extractor.smooth(corners.pyramid, filter),
                                       out.keypoints, fc);
  return out;
}

struct PairResult {
  Extracted left, right;
  std::vector<StereoMatch> matches;
  trace::TaskRecord mo, dr;
};

PairResult match_pair(const testing::PlaneScene& scene, const FrontendOptions& options) {
  const FeatureExtractor extractor(options);
  const StereoMatcher matcher(options);
  PairResult r;
  r.left =
      extract(extractor, scene.left(), options.features_per_image, options.min_feature_distance_px);
  r.right = extract(extractor, scene.right(), options.right_features_per_image,
                    options.right_min_feature_distance_px);
  r.matches = matcher.match(r.left.keypoints, r.left.descriptors, r.right.keypoints,
                            r.right.descriptors, r.mo);
  matcher.refine(r.left.image, r.right.image, r.left.keypoints, r.right.keypoints, r.matches, r.dr);
  return r;
}

/// Fraction of valid matches whose disparity is within `tolerance` of the plane's, and count.
std::pair<double, int> accuracy(const PairResult& r, const testing::PlaneScene& scene,
                                double tolerance) {
  int valid = 0, good = 0;
  for (std::size_t i = 0; i < r.matches.size(); ++i) {
    if (!r.matches[i].valid) continue;
    ++valid;
    const float x = r.left.keypoints[i].pt.x;
    if (std::abs(r.matches[i].disparity - scene.disparity(std::round(x))) < tolerance) ++good;
  }
  return {valid > 0 ? static_cast<double>(good) / valid : 0.0, valid};
}

testing::PlaneScene plane(double a, double b, std::uint64_t seed = 21) {
  testing::PlaneScene scene;
  scene.texture = testing::make_texture({1000, 700}, seed);
  scene.disparity_at_0 = a;
  scene.disparity_slope = b;
  return scene;
}

TEST(StereoMatcher, ConstantDisparityIsRecoveredToSubPixel) {
  const testing::PlaneScene scene = plane(17.35, 0.0);
  const PairResult r = match_pair(scene, FrontendOptions{});
  const auto [fraction, valid] = accuracy(r, scene, 0.25);
  EXPECT_GT(valid, 300);
  EXPECT_GT(fraction, 0.97);
  EXPECT_EQ(r.dr.window_size, 11);
  EXPECT_EQ(r.dr.search_range, 11);
  EXPECT_EQ(r.mo.keypoints, static_cast<std::int64_t>(r.left.keypoints.size()));
  EXPECT_GE(r.dr.windows, valid);
  EXPECT_LE(r.dr.windows, r.dr.keypoints);
}

TEST(StereoMatcher, SlantedPlaneWithinOnePixel) {
  const testing::PlaneScene scene = plane(4.0, 0.05);  // 4 px at the left edge, 36 px at 640
  const PairResult r = match_pair(scene, FrontendOptions{});
  const auto [fraction, valid] = accuracy(r, scene, 1.0);
  EXPECT_GT(valid, 300);
  EXPECT_GT(fraction, 0.95);
}

TEST(StereoMatcher, ComparisonsAreTheCandidatesInTheBandAndRange) {
  const testing::PlaneScene scene = plane(9.0, 0.0);
  FrontendOptions options;
  const PairResult r = match_pair(scene, options);
  // Independent count of the candidate pairs the rules admit.
  std::int64_t expected = 0;
  for (const cv::KeyPoint& l : r.left.keypoints) {
    for (const cv::KeyPoint& k : r.right.keypoints) {
      const double band = options.row_band_px * std::pow(options.scale_factor, k.octave);
      const double d = l.pt.x - k.pt.x;
      if (std::abs(k.octave - l.octave) <= 1 && std::abs(k.pt.y - l.pt.y) <= band && d >= 0 &&
          d <= options.max_disparity_px) {
        ++expected;
      }
    }
  }
  EXPECT_EQ(r.mo.comparisons, expected);
  EXPECT_GT(expected, static_cast<std::int64_t>(r.left.keypoints.size()));
}

TEST(StereoMatcher, NothingMatchesBeyondTheDisparityRange) {
  const testing::PlaneScene scene = plane(40.0, 0.0);
  FrontendOptions options;
  options.max_disparity_px = 30;
  const PairResult r = match_pair(scene, options);
  // With the true match out of range only rare look-alikes remain.
  const auto [fraction, valid] = accuracy(r, scene, 1.0);
  EXPECT_EQ(fraction, 0.0);
  EXPECT_LT(valid, static_cast<int>(r.left.keypoints.size()) / 50);
  options.max_disparity_px = 64;
  const auto [fraction64, valid64] = accuracy(match_pair(scene, options), scene, 1.0);
  EXPECT_GT(valid64, 300);
  EXPECT_GT(fraction64, 0.95);
}

TEST(StereoMatcher, EachRightKeypointServesOneLeftFeature) {
  const testing::PlaneScene scene = plane(12.0, 0.0);
  const PairResult r = match_pair(scene, FrontendOptions{});
  std::vector<int> uses(r.right.keypoints.size(), 0);
  for (const StereoMatch& m : r.matches) {
    if (m.valid) ++uses[static_cast<std::size_t>(m.right_index)];
  }
  for (const int n : uses) EXPECT_LE(n, 1);
}

TEST(StereoMatcher, RefineFindsHalfPixelShiftAndDropsRangeEnds) {
  // Right = left shifted by exactly 6.5 px: SAD costs at 6 and 7 px are mirror images, so the
  // parabola's vertex lies at 6.5. The ORB match is given 3 px off (within +-5) except for every
  // fifth point, placed 9 px off: its best offset is the end of the range, and it is dropped.
  const cv::Mat texture = testing::make_texture({400, 200}, 4);
  cv::Mat left, right;
  cv::GaussianBlur(texture, left, cv::Size(7, 7), 2);
  const cv::Matx23d shift(1, 0, 6.5, 0, 1, 0);
  cv::warpAffine(left, right, cv::Mat(shift), left.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REFLECT_101);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(left, corners, 12, true);
  cv::KeyPointsFilter::runByImageBorder(corners, left.size(), 30);
  cv::KeyPointsFilter::retainBest(corners, 40);
  ASSERT_GE(corners.size(), 20u);
  const FrontendOptions options;
  const StereoMatcher matcher(options);
  std::vector<cv::KeyPoint> lk, rk;
  std::vector<StereoMatch> matches;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    lk.push_back(corners[i]);
    const float off = i % 5 == 0 ? 9.0f : 3.0f;
    rk.emplace_back(corners[i].pt.x - 6.5f + off, corners[i].pt.y, 31);
    StereoMatch m;
    m.valid = true;
    m.right_index = static_cast<int>(i);
    m.right_x = rk.back().pt.x;
    matches.push_back(m);
  }
  trace::TaskRecord dr;
  matcher.refine(left, right, lk, rk, matches, dr);
  EXPECT_EQ(dr.windows, static_cast<std::int64_t>(corners.size()));
  int refined = 0, accurate = 0, dropped_far = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const StereoMatch& m = matches[i];
    if (i % 5 == 0) {
      dropped_far += m.valid ? 0 : 1;
      continue;
    }
    if (!m.valid) continue;
    ++refined;
    if (std::abs(m.disparity - 6.5) < 0.1 && std::abs(m.right_x - (lk[i].pt.x - 6.5)) < 0.1) {
      ++accurate;
    }
  }
  const int far = static_cast<int>((corners.size() + 4) / 5);
  const int near = static_cast<int>(corners.size()) - far;
  EXPECT_EQ(dropped_far, far);
  EXPECT_EQ(refined, near);
  EXPECT_GE(accurate, near * 9 / 10);
}

}  // namespace
}  // namespace edx::frontend
