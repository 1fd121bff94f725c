// Temporal matching (DC, LSS): known image motion, forward-backward rejection, and the LK
// iteration replay against OpenCV's own run.
#include "workloads/frontend/temporal_tracker.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "tests/workloads/frontend/plane_scene.hpp"

namespace edx::frontend {
namespace {

struct Scene {
  testing::PlaneScene plane;
  std::vector<cv::Point2f> points;
};

Scene make_scene() {
  Scene s;
  s.plane.texture = testing::make_texture({1000, 700}, 31);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(s.plane.left(), corners, 30, true);
  for (const cv::KeyPoint& k : corners) {
    if (k.pt.x > 40 && k.pt.y > 40 && k.pt.x < 600 && k.pt.y < 360) s.points.push_back(k.pt);
  }
  return s;
}

TEST(TemporalTracker, PyramidCountsPixelsPerLevel) {
  FrontendOptions options;
  options.lk_max_level = 3;
  const TemporalTracker tracker(options);
  trace::TaskRecord dc;
  const LkPyramid pyramid = tracker.build_pyramid(cv::Mat(480, 752, CV_8U, cv::Scalar(7)), dc);
  EXPECT_EQ(pyramid.max_level, 3);
  EXPECT_EQ(pyramid.mats.size(), 8u);  // image and derivatives per level
  ASSERT_EQ(dc.per_level.size(), 4u);
  EXPECT_EQ(dc.per_level[1].width, 376);
  EXPECT_EQ(dc.per_level[3].height, 60);
  EXPECT_EQ(dc.pixels, 752 * 480 + 376 * 240 + 188 * 120 + 94 * 60);
  EXPECT_EQ(dc.levels, 4);
}

TEST(TemporalTracker, KnownMotionIsTrackedToSubPixel) {
  const Scene s = make_scene();
  ASSERT_GT(s.points.size(), 200u);
  const TemporalTracker tracker(FrontendOptions{});
  trace::TaskRecord dc, lss;
  const cv::Point2d motion(7.4, -3.2);
  const LkPyramid before = tracker.build_pyramid(s.plane.left(), dc);
  const LkPyramid after = tracker.build_pyramid(s.plane.left(motion), dc);
  const TrackResult result = tracker.track(before, after, s.points, lss);
  EXPECT_EQ(lss.iterations, 0);  // counted separately, outside the timing
  tracker.count_iterations(before, after, s.points, result, lss);
  int tracked = 0, accurate = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (!result.tracked[i]) continue;
    ++tracked;
    const cv::Point2f expected = s.points[i] + cv::Point2f(motion);
    if (cv::norm(result.positions[i] - expected) < 0.1) ++accurate;
    EXPECT_LT(result.round_trip_px[i], 1.0f);
  }
  EXPECT_GT(tracked, static_cast<int>(0.95 * static_cast<double>(s.points.size())));
  EXPECT_GT(accurate, static_cast<int>(0.95 * tracked));
  // Work: forward solves for every point plus backward solves of the converged ones.
  EXPECT_GE(lss.points, static_cast<std::int64_t>(s.points.size()) + tracked);
  EXPECT_LE(lss.points, 2 * static_cast<std::int64_t>(s.points.size()));
  EXPECT_EQ(lss.levels, 4);
  EXPECT_GT(lss.iterations, 0);
  std::int64_t iterations = 0;
  for (const trace::LevelWork& level : lss.per_level) {
    iterations += level.iterations;
    EXPECT_GE(level.iterations, level.points);  // at least one update per point solved
    EXPECT_LE(level.iterations, level.points * FrontendOptions{}.lk_max_iterations);
  }
  EXPECT_EQ(iterations, lss.iterations);
}

TEST(TemporalTracker, ChangedContentFailsTheRoundTrip) {
  const Scene s = make_scene();
  const TemporalTracker tracker(FrontendOptions{});
  trace::TaskRecord dc, lss;
  cv::Mat next = s.plane.left(cv::Point2d(2, 1));
  // Replace the right half of the next image with unrelated texture.
  const cv::Mat other = testing::make_texture(next.size(), 99);
  other(cv::Rect(320, 0, 320, 400)).copyTo(next(cv::Rect(320, 0, 320, 400)));
  const TrackResult result = tracker.track(tracker.build_pyramid(s.plane.left(), dc),
                                           tracker.build_pyramid(next, dc), s.points, lss);
  int left_tracked = 0, left_total = 0, right_tracked = 0, right_total = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (s.points[i].x < 280) {
      ++left_total;
      left_tracked += result.tracked[i];
    } else if (s.points[i].x > 360) {
      ++right_total;
      right_tracked += result.tracked[i];
    }
  }
  EXPECT_GT(left_tracked, 0.9 * left_total);
  EXPECT_LT(right_tracked, 0.2 * right_total);
}

TEST(TemporalTracker, ReplayOnIdenticalImagesTakesOneIterationPerPointAndLevel) {
  // J = I: the first update is exactly zero, so OpenCV stops after one iteration everywhere.
  const Scene s = make_scene();
  const TemporalTracker tracker(FrontendOptions{});
  trace::TaskRecord dc;
  const LkPyramid pyramid = tracker.build_pyramid(s.plane.left(), dc);
  const LkReplay replay = replay_lk(pyramid, pyramid, s.points, tracker.forward_call());
  ASSERT_EQ(replay.levels.size(), 4u);
  for (const LkLevelIterations& level : replay.levels) {
    EXPECT_EQ(level.points, static_cast<std::int64_t>(s.points.size()));
    EXPECT_EQ(level.iterations, level.points);
  }
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_EQ(replay.positions[i], s.points[i]);
  }
}

TEST(TemporalTracker, ReplayReproducesOpenCvsResult) {
  const Scene s = make_scene();
  const FrontendOptions options;
  const TemporalTracker tracker(options);
  trace::TaskRecord dc;
  const cv::Point2d motion(-11.3, 5.6);
  const LkPyramid before = tracker.build_pyramid(s.plane.left(), dc);
  const LkPyramid after = tracker.build_pyramid(s.plane.left(motion), dc);
  std::vector<cv::Point2f> opencv_points;
  std::vector<unsigned char> status;
  run_lk(before, after, s.points, tracker.forward_call(), opencv_points, status);
  const LkReplay replay = replay_lk(before, after, s.points, tracker.forward_call());
  std::size_t same = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (replay.status[i] == status[i] &&
        (!status[i] || cv::norm(replay.positions[i] - opencv_points[i]) < 1e-3)) {
      ++same;
    }
  }
  EXPECT_GE(same, s.points.size() * 99 / 100);
  // A motion of 12 px needs several iterations somewhere: more than one per point and level.
  std::int64_t points = 0, iterations = 0;
  for (const LkLevelIterations& level : replay.levels) {
    points += level.points;
    iterations += level.iterations;
  }
  EXPECT_GT(iterations, points);
}

TEST(TemporalTracker, ReplayReproducesOpenCvWithFewerLevels) {
  // Two levels only: a 5 px motion is still within reach.
  const Scene s = make_scene();
  const TemporalTracker tracker(FrontendOptions{});
  trace::TaskRecord dc;
  const cv::Point2d motion(4.2, 2.9);
  const LkPyramid before = tracker.build_pyramid(s.plane.left(), dc);
  const LkPyramid after = tracker.build_pyramid(s.plane.left(motion), dc);
  LkCall call = tracker.forward_call();
  call.max_level = 1;
  std::vector<cv::Point2f> opencv_points;
  std::vector<unsigned char> status;
  run_lk(before, after, s.points, call, opencv_points, status);
  const LkReplay replay = replay_lk(before, after, s.points, call);
  ASSERT_EQ(replay.levels.size(), 2u);
  std::size_t same = 0, accurate = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (replay.status[i] == status[i] &&
        (!status[i] || cv::norm(replay.positions[i] - opencv_points[i]) < 1e-3)) {
      ++same;
    }
    if (status[i] && cv::norm(opencv_points[i] - (s.points[i] + cv::Point2f(motion))) < 0.1) {
      ++accurate;
    }
  }
  EXPECT_GE(same, s.points.size() * 99 / 100);
  EXPECT_GE(accurate, s.points.size() * 9 / 10);
}

TEST(TemporalTracker, NoPreviousFrameMeansNoWork) {
  const TemporalTracker tracker(FrontendOptions{});
  trace::TaskRecord dc, lss;
  const LkPyramid current = tracker.build_pyramid(cv::Mat(200, 200, CV_8U, cv::Scalar(1)), dc);
  const TrackResult result = tracker.track(LkPyramid{}, current, {}, lss);
  EXPECT_TRUE(result.positions.empty());
  EXPECT_EQ(lss.points, 0);
  EXPECT_EQ(lss.iterations, 0);
  EXPECT_EQ(lss.host_ns, 0);
}

}  // namespace
}  // namespace edx::frontend
