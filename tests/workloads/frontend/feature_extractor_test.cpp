// Feature extraction (FD, IF, FC): budget, spread, margins, adaptive threshold, work counts, and
// descriptors identical to cv::ORB's own.
#include "workloads/frontend/feature_extractor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "tests/workloads/frontend/plane_scene.hpp"

namespace edx::frontend {
namespace {

using trace::Image;
using trace::Task;

trace::TaskRecord task(Task t) {
  trace::TaskRecord record;
  record.task = t;
  record.image = Image::Left;
  return record;
}

cv::Mat textured_image(cv::Size size = {640, 400}, std::uint64_t seed = 3) {
  return testing::make_texture(size, seed);
}

TEST(FeatureExtractor, PyramidFollowsOrbSizes) {
  FrontendOptions options;
  options.pyramid_levels = 4;
  const FeatureExtractor extractor(options);
  const ImagePyramid pyramid = extractor.build_pyramid(cv::Mat(480, 752, CV_8U, cv::Scalar(0)));
  ASSERT_EQ(pyramid.levels.size(), 4u);
  // cvRound(752 / 1.2^l) x cvRound(480 / 1.2^l)
  EXPECT_EQ(pyramid.levels[1].size(), cv::Size(627, 400));
  EXPECT_EQ(pyramid.levels[2].size(), cv::Size(522, 333));
  EXPECT_EQ(pyramid.levels[3].size(), cv::Size(435, 278));
  EXPECT_NEAR(pyramid.scales[3], 1.728, 1e-6);
}

TEST(FeatureExtractor, DetectCountsPixelsAndCandidatesPerLevel) {
  const FrontendOptions options;
  const FeatureExtractor extractor(options);
  const cv::Mat image = textured_image();
  trace::TaskRecord fd = task(Task::FD);
  const DetectedCorners corners = extractor.detect(image, fd);
  ASSERT_EQ(fd.per_level.size(), 4u);
  std::int64_t pixels = 0;
  for (std::size_t l = 0; l < fd.per_level.size(); ++l) {
    const cv::Mat& level = corners.pyramid.levels[l];
    EXPECT_EQ(fd.per_level[l].pixels, static_cast<std::int64_t>(level.cols) * level.rows);
    pixels += fd.per_level[l].pixels;
  }
  EXPECT_EQ(fd.pixels, pixels);
  EXPECT_EQ(fd.levels, 4);
  std::size_t corners_found = 0;
  for (const auto& level : corners.ranked) corners_found += level.size();
  // Non-maximum suppression keeps a subset of the segment-test corners.
  EXPECT_GT(corners_found, 500u);
  EXPECT_GT(fd.candidates, static_cast<std::int64_t>(corners_found));
  EXPECT_GT(fd.host_ns, 0);
}

/// The first `count` images of a folder of PNGs, in name order, grayscale.
std::vector<cv::Mat> first_images(const std::filesystem::path& folder, std::size_t count) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() == ".png") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<cv::Mat> images;
  for (std::size_t i = 0; i < std::min(count, files.size()); ++i) {
    images.push_back(cv::imread(files[i].string(), cv::IMREAD_GRAYSCALE));
  }
  return images;
}

TEST(FastWithSuppression, ScoresAHandMadeCornerByItsWeakestArcPixel) {
  // Centre 100 on a 100 background, circle pixels 0..8 (9 contiguous: (0,3) clockwise to
  // (0,-3)) at 70: d = 30 on the arc, 0 elsewhere, so at threshold 20 the score is 30 - 1.
  cv::Mat image(11, 11, CV_8U, cv::Scalar(100));
  const int circle[9][2] = {{0, 3},  {1, 3},  {2, 2},  {3, 1}, {3, 0},
                            {3, -1}, {2, -2}, {1, -3}, {0, -3}};
  for (const auto& o : circle) image.at<uchar>(5 + o[1], 5 + o[0]) = 70;
  image.at<uchar>(5 + 3, 5 + 1) = 75;  // the arc's weakest pixel: d = 25, score 24
  std::int64_t candidates = 0;
  const std::vector<cv::KeyPoint> kept = fast_with_suppression(image, 20, candidates);
  const auto centre = std::find_if(kept.begin(), kept.end(),
                                   [](const cv::KeyPoint& k) { return k.pt == cv::Point2f(5, 5); });
  ASSERT_NE(centre, kept.end());
  EXPECT_EQ(centre->response, 24.f);
  EXPECT_EQ(centre->size, 7.f);
  std::vector<cv::KeyPoint> raw;
  cv::FAST(image, raw, 20, false);
  EXPECT_EQ(candidates, static_cast<std::int64_t>(raw.size()));
}

TEST(FastWithSuppression, EqualsCvFastWithSuppressionOnRealFrames) {
  // EuRoC and KITTI frames, whole and in ROIs (odd offsets and sizes, as the grid's retries
  // cut them), at the frontend's thresholds and others: the same keypoints in the same order,
  // and the candidates are cv::FAST's corners without suppression.
  const std::filesystem::path data(EDX_SHARED_DATA_DIR);
  std::vector<cv::Mat> images =
      first_images(data / "euroc_v101_micro" / "mav0" / "cam0" / "data", 3);
  for (const cv::Mat& image :
       first_images(data / "kitti_odometry_excerpt" / "sequences" / "01" / "image_0", 2)) {
    images.push_back(image);
  }
  ASSERT_EQ(images.size(), 5u);
  std::size_t compared = 0;
  for (const cv::Mat& image : images) {
    ASSERT_FALSE(image.empty());
    cv::Mat half;
    cv::resize(image, half, image.size() / 2, 0, 0, cv::INTER_LINEAR_EXACT);
    for (const cv::Mat* source : std::array<const cv::Mat*, 2>{&image, &half}) {
      const cv::Size size = source->size();
      const std::vector<cv::Rect> rois = {
          cv::Rect({0, 0}, size), cv::Rect(16, 16, size.width - 32, size.height - 32),
          cv::Rect(41, 23, 70, 38), cv::Rect(size.width - 100, 7, 99, 51), cv::Rect(3, 5, 8, 9)};
      for (const cv::Rect& roi : rois) {
        for (const int threshold : {5, 7, 20, 40}) {
          const cv::Mat view = (*source)(roi);
          std::vector<cv::KeyPoint> expected, raw;
          cv::FAST(view, expected, threshold, true);
          cv::FAST(view, raw, threshold, false);
          std::int64_t candidates = 0;
          const std::vector<cv::KeyPoint> ours = fast_with_suppression(view, threshold, candidates);
          EXPECT_EQ(candidates, static_cast<std::int64_t>(raw.size()));
          ASSERT_EQ(ours.size(), expected.size()) << roi << " threshold " << threshold;
          for (std::size_t i = 0; i < ours.size(); ++i) {
            EXPECT_EQ(ours[i].pt, expected[i].pt) << i;
            EXPECT_EQ(ours[i].response, expected[i].response) << i;
            EXPECT_EQ(ours[i].size, expected[i].size) << i;
            EXPECT_EQ(ours[i].angle, expected[i].angle) << i;
            EXPECT_EQ(ours[i].octave, expected[i].octave) << i;
          }
          compared += ours.size();
        }
      }
    }
  }
  EXPECT_GT(compared, 10000u);
}

TEST(FeatureExtractor, SelectKeepsBudgetMarginAndDistance) {
  FrontendOptions options;
  options.features_per_image = 300;
  const FeatureExtractor extractor(options);
  trace::TaskRecord fd = task(Task::FD);
  const DetectedCorners corners = extractor.detect(textured_image(), fd);
  const std::vector<cv::KeyPoint> kept =
      extractor.select(corners, {}, 300, options.min_feature_distance_px, fd);
  EXPECT_EQ(kept.size(), 300u);
  EXPECT_EQ(fd.keypoints, 300);
  std::vector<int> per_level(4, 0);
  for (std::size_t i = 0; i < kept.size(); ++i) {
    EXPECT_TRUE(extractor.describable(corners.pyramid, kept[i].pt, kept[i].octave));
    ++per_level[static_cast<std::size_t>(kept[i].octave)];
    for (std::size_t j = 0; j < i; ++j) {
      // Centres are rounded before the mask test: allow the rounding of both points.
      EXPECT_GT(cv::norm(kept[i].pt - kept[j].pt), options.min_feature_distance_px - 1.5);
    }
  }
  // Every level contributes (ORB's geometric share).
  for (const int n : per_level) EXPECT_GT(n, 0);
}

TEST(FeatureExtractor, SelectKeepsAwayFromOccupiedPoints) {
  const FrontendOptions options;
  const FeatureExtractor extractor(options);
  trace::TaskRecord fd = task(Task::FD);
  const DetectedCorners corners = extractor.detect(textured_image(), fd);
  // Occupy the whole left half with a dense lattice: new features go right only.
  std::vector<cv::Point2f> occupied;
  for (int y = 0; y < 400; y += 4) {
    for (int x = 0; x < 320; x += 4)
      occupied.emplace_back(static_cast<float>(x), static_cast<float>(y));
  }
  const std::vector<cv::KeyPoint> kept =
      extractor.select(corners, occupied, 200, options.min_feature_distance_px, fd);
  ASSERT_FALSE(kept.empty());
  for (const cv::KeyPoint& k : kept) EXPECT_GT(k.pt.x, 320 + options.min_feature_distance_px - 4);
  EXPECT_TRUE(extractor.select(corners, {}, 0, 8, fd).empty());
}

TEST(FeatureExtractor, LowContrastCellsAreSearchedWithTheMinimumThreshold) {
  // Left half: strong texture; right half: shapes within +-14 grey levels of the background,
  // below fast_threshold 20 but above fast_min_threshold 7.
  cv::Mat image = testing::make_texture({640, 400}, 11);
  const cv::Mat faint = testing::make_texture({640, 400}, 12, 0.1);
  faint(cv::Rect(320, 0, 320, 400)).copyTo(image(cv::Rect(320, 0, 320, 400)));

  FrontendOptions adaptive;
  adaptive.features_per_image = 400;
  FrontendOptions fixed = adaptive;
  fixed.fast_min_threshold = fixed.fast_threshold;  // no retry with a lower threshold
  auto right_half = [&](const FrontendOptions& options) {
    const FeatureExtractor extractor(options);
    trace::TaskRecord fd = task(Task::FD);
    int count = 0;
    for (const auto& k : extractor.select(extractor.detect(image, fd), {}, 400, 8, fd)) {
      if (k.pt.x > 340) ++count;
    }
    return count;
  };
  EXPECT_LT(right_half(fixed), 5);
  EXPECT_GT(right_half(adaptive), 50);
}

TEST(FeatureExtractor, AnglesEqualCvOrbsAndDescriptorsAreOrbsOnTheFilteredImage) {
  const cv::Mat image = textured_image();
  // cv::ORB on one level: detection and its orientation.
  cv::Ptr<cv::ORB> orb = cv::ORB::create(300, 1.2f, 1);
  std::vector<cv::KeyPoint> orb_keypoints;
  orb->detect(image, orb_keypoints);
  ASSERT_GT(orb_keypoints.size(), 100u);

  const FeatureExtractor extractor(FrontendOptions{});
  const ImagePyramid pyramid = extractor.build_pyramid(image);
  trace::TaskRecord filter = task(Task::IF), fc = task(Task::FC);
  const ImagePyramid smoothed = extractor.smooth(pyramid, filter);
  std::vector<cv::KeyPoint> ours = orb_keypoints;
  for (cv::KeyPoint& k : ours) k.angle = -1;
  const cv::Mat descriptors = extractor.describe(pyramid, smoothed, ours, fc);

  // cv::ORB::compute with ORB's angles on the 7x7 sigma-2 filtered image.
  cv::Mat filtered, expected;
  cv::GaussianBlur(image, filtered, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
  std::vector<cv::KeyPoint> given = orb_keypoints;
  orb->compute(filtered, given, expected);
  ASSERT_EQ(descriptors.rows, expected.rows);
  for (std::size_t i = 0; i < ours.size(); ++i) {
    EXPECT_EQ(ours[i].angle, orb_keypoints[i].angle) << i;  // the same moments, exactly
    EXPECT_EQ(cv::norm(descriptors.row(static_cast<int>(i)), expected.row(static_cast<int>(i)),
                       cv::NORM_HAMMING),
              0)
        << i;
  }
  EXPECT_EQ(fc.descriptors, static_cast<std::int64_t>(ours.size()));
  EXPECT_EQ(fc.keypoints, static_cast<std::int64_t>(ours.size()));
  EXPECT_EQ(fc.levels, 1);  // only level 0 had keypoints
  EXPECT_EQ(fc.pixels, 640 * 400);
}

TEST(FeatureExtractor, DescriptorsAreRotationInvariant) {
  // A corner rotated by 90 degrees about its centre keeps (almost) the same descriptor and its
  // orientation turns by 90 degrees.
  const cv::Mat image = textured_image({401, 401}, 5);
  cv::Mat rotated;
  cv::rotate(image, rotated, cv::ROTATE_90_CLOCKWISE);
  const FeatureExtractor extractor(FrontendOptions{});
  std::vector<cv::KeyPoint> a{cv::KeyPoint(200, 200, 31, -1, 0, 0)};
  std::vector<cv::KeyPoint> b{cv::KeyPoint(200, 200, 31, -1, 0, 0)};
  trace::TaskRecord filter = task(Task::IF), fc = task(Task::FC);
  const ImagePyramid pa = extractor.build_pyramid(image), pb = extractor.build_pyramid(rotated);
  const cv::Mat da = extractor.describe(pa, extractor.smooth(pa, filter), a, fc);
  const cv::Mat db = extractor.describe(pb, extractor.smooth(pb, filter), b, fc);
  const double turn = std::fmod(b[0].angle - a[0].angle + 360.0, 360.0);
  EXPECT_NEAR(turn, 90.0, 2.0);
  EXPECT_LT(cv::norm(da, db, cv::NORM_HAMMING), 30);
  // Without the orientation the same pair differs much more.
  cv::Ptr<cv::ORB> orb = cv::ORB::create(10, 1.2f, 1, 19);
  std::vector<cv::KeyPoint> ua{cv::KeyPoint(200, 200, 31, 0, 0, 0)};
  std::vector<cv::KeyPoint> ub{cv::KeyPoint(200, 200, 31, 0, 0, 0)};
  cv::Mat uda, udb;
  orb->compute(image, ua, uda);
  orb->compute(rotated, ub, udb);
  EXPECT_GT(cv::norm(uda, udb, cv::NORM_HAMMING), 60);
}

TEST(FeatureExtractor, SmoothFiltersEveryLevelWithOrbsGaussian) {
  const FeatureExtractor extractor(FrontendOptions{});
  const ImagePyramid pyramid = extractor.build_pyramid(textured_image());
  trace::TaskRecord filter = task(Task::IF);
  const ImagePyramid smoothed = extractor.smooth(pyramid, filter);
  ASSERT_EQ(smoothed.levels.size(), pyramid.levels.size());
  std::int64_t pixels = 0;
  for (std::size_t l = 0; l < pyramid.levels.size(); ++l) {
    cv::Mat expected;
    cv::GaussianBlur(pyramid.levels[l], expected, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
    EXPECT_EQ(cv::norm(smoothed.levels[l], expected, cv::NORM_INF), 0);
    EXPECT_EQ(smoothed.scales[l], pyramid.scales[l]);
    pixels += static_cast<std::int64_t>(expected.total());
  }
  EXPECT_EQ(filter.pixels, pixels);
  EXPECT_EQ(filter.window_size, 7);
  EXPECT_EQ(filter.levels, 4);
  EXPECT_EQ(filter.per_level.size(), 4u);
}

TEST(FeatureExtractor, DescribeRejectsPointsInsideTheMargin) {
  const FeatureExtractor extractor(FrontendOptions{});
  const ImagePyramid pyramid = extractor.build_pyramid(textured_image());
  EXPECT_FALSE(extractor.describable(pyramid, {10, 200}, 0));
  EXPECT_TRUE(extractor.describable(pyramid, {19, 200}, 0));
  // 25 px from the border is 25 / 1.728 = 14.5 px on level 3: too close there.
  EXPECT_FALSE(extractor.describable(pyramid, {25, 200}, 3));
  std::vector<cv::KeyPoint> bad{cv::KeyPoint(10, 200, 31, -1, 0, 0)};
  trace::TaskRecord filter = task(Task::IF), fc = task(Task::FC);
  EXPECT_THROW(extractor.describe(pyramid, extractor.smooth(pyramid, filter), bad, fc),
               std::logic_error);
}

/// Level-0 coordinate of every pixel of every pyramid level, measured: the pyramid of a ramp
/// image (value = 64 x, 16-bit) holds 64 X0(x_l) at level pixel x_l, as bilinear resizing
/// reproduces a linear function exactly (up to the fixed-point weights and 16-bit rounding, < 0.02
/// px).
std::vector<cv::Mat> level0_coordinate(const FeatureExtractor& extractor, cv::Size size,
                                       bool along_y) {
  cv::Mat ramp(size, CV_16U);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) ramp.at<std::uint16_t>(y, x) = 64 * (along_y ? y : x);
  }
  std::vector<cv::Mat> out;
  for (const cv::Mat& level : extractor.build_pyramid(ramp).levels) {
    cv::Mat coordinate;
    level.convertTo(coordinate, CV_64F, 1.0 / 64);
    out.push_back(coordinate);
  }
  return out;
}

TEST(FeatureExtractor, LevelPixelsMapToLevel0ThroughPixelCentres) {
  // Hand-computed: 640x360 at scale 1.2 gives levels 533x300, 444x250, 370x208; level-3 pixel
  // (200, 200) sits at ((200.5) 640 / 370 - 0.5, (200.5) 360 / 208 - 0.5) = (346.31, 346.52),
  // not at 1.728 (200, 200) = (345.6, 345.6).
  const FeatureExtractor extractor(FrontendOptions{});
  const cv::Size size(640, 360);
  const ImagePyramid pyramid = extractor.build_pyramid(cv::Mat(size, CV_8U, cv::Scalar(0)));
  ASSERT_EQ(pyramid.levels[3].size(), cv::Size(370, 208));
  const cv::Point2f p = pyramid.to_level0({200, 200}, 3);
  EXPECT_NEAR(p.x, 200.5 * 640 / 370 - 0.5, 1e-3);
  EXPECT_NEAR(p.y, 200.5 * 360 / 208 - 0.5, 1e-3);
  const cv::Point2f back = pyramid.from_level0(p, 3);
  EXPECT_NEAR(back.x, 200, 1e-3);
  EXPECT_NEAR(back.y, 200, 1e-3);
  // Against cv::resize itself, away from the clamped border.
  const std::vector<cv::Mat> xs = level0_coordinate(extractor, size, false);
  const std::vector<cv::Mat> ys = level0_coordinate(extractor, size, true);
  for (std::size_t l = 1; l < xs.size(); ++l) {
    for (int y = 5; y < xs[l].rows - 5; y += 7) {
      for (int x = 5; x < xs[l].cols - 5; x += 7) {
        const cv::Point2f q = pyramid.to_level0(cv::Point2f(x, y), l);
        ASSERT_NEAR(q.x, xs[l].at<double>(y, x), 0.02) << "level " << l << " x " << x;
        ASSERT_NEAR(q.y, ys[l].at<double>(y, x), 0.02) << "level " << l << " y " << y;
      }
    }
  }
}

TEST(FeatureExtractor, KeypointsOfHigherLevelsSitOnTheirLevelPixelCentres) {
  // Every detected keypoint must be the level-0 position of a level pixel, as cv::resize
  // placed it (measured with a ramp image). Scaling level coordinates by s^l instead misses by
  // 0.1 px on level 1 and up to 0.9 px on level 3 (x and y alike).
  const FeatureExtractor extractor(FrontendOptions{});
  const cv::Mat image = textured_image({640, 360});
  trace::TaskRecord fd = task(Task::FD);
  const DetectedCorners corners = extractor.detect(image, fd);
  const std::vector<cv::Mat> xs = level0_coordinate(extractor, image.size(), false);
  const std::vector<cv::Mat> ys = level0_coordinate(extractor, image.size(), true);
  int checked = 0;
  for (std::size_t l = 1; l < corners.ranked.size(); ++l) {
    for (const cv::KeyPoint& k : corners.ranked[l]) {
      // Nearest level column and row by the measured coordinates.
      double dx = 1e9, dy = 1e9;
      for (int x = 0; x < xs[l].cols; ++x) {
        dx = std::min(dx, std::abs(xs[l].at<double>(0, x) - k.pt.x));
      }
      for (int y = 0; y < ys[l].rows; ++y) {
        dy = std::min(dy, std::abs(ys[l].at<double>(y, 0) - k.pt.y));
      }
      ASSERT_LT(dx, 0.02) << "level " << l << " at " << k.pt;
      ASSERT_LT(dy, 0.02) << "level " << l << " at " << k.pt;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

}  // namespace
}  // namespace edx::frontend
