// The whole frontend on a textured plane with known disparity and motion: quality, track ids,
// the ten task rows and their counts, determinism, and refusal of bad images; the frontend
// benchmark's serial mode.
#include "workloads/frontend/stereo_frontend.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include "tests/workloads/frontend/plane_scene.hpp"
#include "workloads/frontend/benchmark.hpp"

namespace edx::frontend {
namespace {

using ::testing::HasSubstr;
using testing::PlaneScene;
using trace::Image;
using trace::Task;

PlaneScene slanted_plane() {
  PlaneScene scene;
  scene.texture = testing::make_texture({1200, 900}, 7);
  scene.disparity_at_0 = 6.0;
  scene.disparity_slope = 0.02;  // 6 px at the left edge, 18.8 px at the right
  return scene;
}

/// Frame t shows the plane moved by t * kStep.
const cv::Point2d kStep(3.3, -1.7);

std::vector<FrontendFrame> run(const PlaneScene& scene, int frames,
                               const FrontendOptions& options = {}) {
  StereoFrontend frontend(options, {400, 0.1});
  std::vector<FrontendFrame> out;
  for (int t = 0; t < frames; ++t) {
    out.push_back(frontend.process(scene.left(kStep * t), scene.right(kStep * t)));
  }
  return out;
}

TEST(StereoFrontend, StereoAndTracksMatchThePlane) {
  const PlaneScene scene = slanted_plane();
  const std::vector<FrontendFrame> frames = run(scene, 4);
  std::map<std::int64_t, cv::Point2f> previous;
  std::vector<float> residuals;  // LK residuals of the tracked features
  for (const FrontendFrame& frame : frames) {
    int stereo = 0, stereo_good = 0, tracked = 0, tracked_good = 0;
    for (const Feature& f : frame.features) {
      if (f.stereo) {
        ++stereo;
        const double expected = scene.disparity(std::round(f.left.x));
        if (std::abs(f.disparity - expected) < 0.5) ++stereo_good;
        EXPECT_FLOAT_EQ(f.right.x, f.left.x - f.disparity);
        EXPECT_FLOAT_EQ(f.right.y, f.left.y);
        EXPECT_NEAR(f.depth_m, 400 * 0.1 / f.disparity, 1e-9);
        EXPECT_GE(f.hamming, 0);
      }
      if (f.age > 0) {
        ++tracked;
        ASSERT_TRUE(previous.contains(f.id)) << "track " << f.id << " was not in the last frame";
        const cv::Point2f expected = previous.at(f.id) + cv::Point2f(kStep);
        if (cv::norm(f.left - expected) < 0.25) ++tracked_good;
        // The match that brought it here: a converged LK window on a shifted copy of the
        // texture leaves only the interpolation's residual (mean absolute grey levels; a
        // window that slipped off would leave tens), and a round trip under the bar.
        EXPECT_GE(f.lk_residual, 0.0f);
        EXPECT_LT(f.lk_residual, 8.0f);
        residuals.push_back(f.lk_residual);
        EXPECT_GE(f.round_trip_px, 0.0f);
        EXPECT_LT(f.round_trip_px, FrontendOptions{}.fb_threshold_px);
      } else {
        EXPECT_EQ(f.lk_residual, -1.0f);  // new features have no temporal match
        EXPECT_EQ(f.round_trip_px, -1.0f);
      }
    }
    EXPECT_GT(stereo, frame.stats.left_keypoints / 2);
    EXPECT_GE(stereo_good, stereo * 95 / 100);
    EXPECT_GE(tracked_good, tracked * 95 / 100);
    EXPECT_EQ(stereo, frame.stats.stereo_matches);
    EXPECT_EQ(tracked, frame.stats.tracked);
    previous.clear();
    for (const Feature& f : frame.features) previous[f.id] = f.left;
  }
  // After the first frame most features are tracks.
  EXPECT_GT(frames.back().stats.tracked, frames.back().stats.left_keypoints * 8 / 10);
  ASSERT_FALSE(residuals.empty());
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  EXPECT_LT(residuals[residuals.size() / 2], 1.0f);  // median, grey levels
}

TEST(StereoFrontend, IdsAreUniqueAndTracksAge) {
  const std::vector<FrontendFrame> frames = run(slanted_plane(), 4);
  std::map<std::int64_t, int> age_seen;
  for (const FrontendFrame& frame : frames) {
    std::int64_t last_id = -1;
    for (const Feature& f : frame.features) {
      EXPECT_GT(f.id, last_id);  // ascending: tracks first (old ids), then new ones
      last_id = f.id;
      if (f.age == 0) {
        EXPECT_FALSE(age_seen.contains(f.id)) << "new feature reuses id " << f.id;
      } else {
        EXPECT_EQ(age_seen.at(f.id), f.age - 1);
      }
      age_seen[f.id] = f.age;
    }
    EXPECT_EQ(frame.stats.new_features + frame.stats.tracked, frame.stats.left_keypoints);
    EXPECT_LE(frame.stats.left_keypoints, FrontendOptions{}.features_per_image);
    EXPECT_LE(frame.stats.right_keypoints, FrontendOptions{}.right_features_per_image);
  }
  const auto oldest = std::max_element(age_seen.begin(), age_seen.end(),
                                       [](auto a, auto b) { return a.second < b.second; });
  EXPECT_EQ(oldest->second, 3);
}

TEST(StereoFrontend, TenTaskRowsWithConsistentCounts) {
  const std::vector<FrontendFrame> frames = run(slanted_plane(), 3);
  const std::vector<std::pair<Task, Image>> layout = {
      {Task::FD, Image::Left},  {Task::IF, Image::Left},  {Task::FD, Image::Right},
      {Task::IF, Image::Right}, {Task::DC, Image::Left},  {Task::LSS, Image::Left},
      {Task::FC, Image::Left},  {Task::FC, Image::Right}, {Task::MO, Image::Stereo},
      {Task::DR, Image::Stereo}};
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const FrontendFrame& frame = frames[n];
    ASSERT_EQ(frame.tasks.size(), layout.size());
    std::int64_t sum_ns = 0;
    for (std::size_t i = 0; i < layout.size(); ++i) {
      EXPECT_EQ(frame.tasks[i].task, layout[i].first) << i;
      EXPECT_EQ(frame.tasks[i].image, layout[i].second) << i;
      sum_ns += frame.tasks[i].host_ns;
    }
    const auto& t = frame.tasks;
    const auto& s = frame.stats;
    EXPECT_EQ(t[0].keypoints, s.new_features);     // FD L: new features only
    EXPECT_EQ(t[2].keypoints, s.right_keypoints);  // FD R
    EXPECT_EQ(t[0].pixels, t[2].pixels);
    EXPECT_EQ(t[0].levels, 4);
    EXPECT_EQ(t[1].pixels, t[0].pixels);  // IF filters the whole FD pyramid
    EXPECT_EQ(t[1].levels, 4);
    EXPECT_EQ(t[4].pixels, 640 * 400 + 320 * 200 + 160 * 100 + 80 * 50);  // DC, 4 LK levels
    EXPECT_EQ(t[6].descriptors, s.left_keypoints);   // FC L: tracks and new features
    EXPECT_EQ(t[7].descriptors, s.right_keypoints);  // FC R
    EXPECT_EQ(t[8].keypoints, s.left_keypoints);     // MO handles every left feature
    EXPECT_GE(t[8].comparisons, s.stereo_matches);
    EXPECT_GE(t[9].windows, s.stereo_matches);  // DR refined at least the survivors
    EXPECT_EQ(t[9].window_size, 11);
    EXPECT_EQ(t[9].search_range, 11);
    if (n == 0) {
      EXPECT_EQ(t[5].points, 0);  // nothing to track yet
      EXPECT_EQ(t[4].points, 0);
    } else {
      EXPECT_EQ(t[4].points, frames[n - 1].stats.left_keypoints);
      EXPECT_GE(t[5].points, frames[n - 1].stats.left_keypoints + s.tracked);
      EXPECT_GT(t[5].iterations, t[5].points);
      EXPECT_EQ(t[5].levels, 4);
    }
    // Left and right run on two threads: the frame takes less than the sum of its tasks, but
    // at least the longest task.
    EXPECT_GT(frame.host_ns, 0);
    std::int64_t longest = 0;
    for (const auto& task : t) longest = std::max(longest, task.host_ns);
    EXPECT_GE(frame.host_ns, longest);
    EXPECT_LE(frame.host_ns, sum_ns + 50'000'000);
  }
}

TEST(StereoFrontend, SameInputSameOutput) {
  const PlaneScene scene = slanted_plane();
  FrontendOptions sequential;
  sequential.parallel_images = false;
  const std::vector<FrontendFrame> a = run(scene, 3);
  const std::vector<FrontendFrame> b = run(scene, 3, sequential);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t n = 0; n < a.size(); ++n) {
    ASSERT_EQ(a[n].features.size(), b[n].features.size());
    for (std::size_t i = 0; i < a[n].features.size(); ++i) {
      const Feature &x = a[n].features[i], &y = b[n].features[i];
      EXPECT_EQ(x.id, y.id);
      EXPECT_EQ(x.left, y.left);
      EXPECT_EQ(x.descriptor, y.descriptor);
      EXPECT_EQ(x.stereo, y.stereo);
      EXPECT_EQ(x.disparity, y.disparity);
      EXPECT_EQ(x.angle, y.angle);
      EXPECT_EQ(x.lk_residual, y.lk_residual);
      EXPECT_EQ(x.round_trip_px, y.round_trip_px);
    }
    // The parallel jobs' span is at most their work; without parallel_images it is the work.
    EXPECT_GT(a[n].span_ns, 0);
    EXPECT_LE(a[n].span_ns, a[n].host_ns);
    EXPECT_EQ(b[n].span_ns, b[n].host_ns);
    for (std::size_t i = 0; i < a[n].tasks.size(); ++i) {
      trace::TaskRecord ta = a[n].tasks[i], tb = b[n].tasks[i];
      ta.host_ns = tb.host_ns = 0;
      EXPECT_EQ(ta, tb) << "task row " << i;
    }
  }
}

TEST(StereoFrontend, ResetStartsWithoutTracksButKeepsCountingIds) {
  const PlaneScene scene = slanted_plane();
  StereoFrontend frontend({}, {400, 0.1});
  const FrontendFrame first = frontend.process(scene.left(), scene.right());
  frontend.reset();
  const FrontendFrame again = frontend.process(scene.left(kStep), scene.right(kStep));
  EXPECT_EQ(again.stats.tracked, 0);
  EXPECT_GT(again.features.front().id, first.features.back().id);
}

std::string process_error(StereoFrontend& frontend, const cv::Mat& left, const cv::Mat& right) {
  try {
    frontend.process(left, right);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(StereoFrontend, BadImagesAreNamed) {
  const PlaneScene scene = slanted_plane();
  StereoFrontend frontend({}, {400, 0.1});
  EXPECT_THAT(process_error(frontend, cv::Mat(), scene.right()),
              HasSubstr("frame 0: left image is empty"));
  cv::Mat colour;
  cv::cvtColor(scene.left(), colour, cv::COLOR_GRAY2BGR);
  EXPECT_THAT(process_error(frontend, scene.left(), colour),
              HasSubstr("frame 0: right image has 3 channel(s)"));
  EXPECT_THAT(process_error(frontend, scene.left(), scene.right()(cv::Rect(0, 0, 600, 400))),
              HasSubstr("frame 0: left image is 640x400 but right is 600x400"));
  EXPECT_THAT(process_error(frontend, cv::Mat(40, 40, CV_8U), cv::Mat(40, 40, CV_8U)),
              HasSubstr("at least 64x64"));
  ASSERT_EQ(process_error(frontend, scene.left(), scene.right()), "");
  cv::Mat smaller_left, smaller_right;
  cv::resize(scene.left(), smaller_left, {320, 200});
  cv::resize(scene.right(), smaller_right, {320, 200});
  EXPECT_THAT(process_error(frontend, smaller_left, smaller_right),
              HasSubstr("frame 1: images are 320x200 but the sequence started at 640x400"));
}

TEST(StereoFrontend, RejectsBadOptionsAndCamera) {
  FrontendOptions bad;
  bad.features_per_image = 0;
  EXPECT_THROW(StereoFrontend(bad, {400, 0.1}), std::runtime_error);
  EXPECT_THROW(StereoFrontend({}, {400, 0.0}), std::runtime_error);
  EXPECT_THROW(StereoFrontend({}, {-1, 0.1}), std::runtime_error);
}

// run_frontend_benchmark's serial mode (`edx-bench frontend --serial`) does the same work as the
// parallel one, counts its span as its CPU time, and gives OpenCV's threads back.
FrontendBenchmarkOptions euroc_options(bool parallel) {
  FrontendBenchmarkOptions options;
  options.dataset_path = std::filesystem::path(EDX_SHARED_DATA_DIR) / "euroc_v101_micro";
  options.format = datasets::DatasetFormat::kEuroc;
  options.resolutions = {{320, 240}};
  options.frames = 9;
  options.warmup = 3;
  options.frontend.parallel_images = parallel;
  return options;
}

TEST(FrontendBenchmark, SerialDoesTheParallelWorkOnOneThread) {
  cv::setNumThreads(2);
  const int threads = cv::getNumThreads();
  const auto serial = run_frontend_benchmark(euroc_options(false));
  EXPECT_EQ(cv::getNumThreads(), threads);  // OpenCV's setting back after the serial run
  const auto parallel = run_frontend_benchmark(euroc_options(true));
  ASSERT_EQ(serial.size(), 1u);
  ASSERT_EQ(parallel.size(), 1u);
  EXPECT_EQ(serial[0].frames, 6u);
  // The same features, tracks and matches per frame: the same work either way.
  EXPECT_GT(serial[0].left_keypoints, 100);
  EXPECT_EQ(serial[0].left_keypoints, parallel[0].left_keypoints);
  EXPECT_EQ(serial[0].stereo_matches, parallel[0].stereo_matches);
  EXPECT_EQ(serial[0].tracked, parallel[0].tracked);
  // One thread: each frame's span is its CPU time.
  EXPECT_GT(serial[0].cpu_fps, 0);
  EXPECT_DOUBLE_EQ(serial[0].span_fps, serial[0].cpu_fps);
}

}  // namespace
}  // namespace edx::frontend
