// The frontend DES against the analytical critical path of the task graph (paper Sec. V-B) on
// inputs whose task cycles are known exactly.
#include "arch/frontend/frontend_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "arch/frontend/task_timing.hpp"
#include "tests/arch/frontend/frontend_test_support.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

using trace::Image;
using trace::Task;

/// Config where one cycle is 10 ns and each task's cycles equal one count of its row (rows
/// without per-level work have no stencil halo).
FrontendConfig unit_config() {
  FrontendConfig c;
  c.clock_mhz = 100;
  c.fe_pixels_per_cycle = 1;
  testing::set_unit(c, Task::FC, "{patch_rows_per_cycle: 1, tests_per_cycle: 256}");
  testing::set_unit(c, Task::MO, "{comparators: 1}");
  testing::set_unit(c, Task::DR, "{pixels_per_cycle: 1}");
  testing::set_unit(c, Task::DC, "{pixels_per_cycle: 1}");
  testing::set_unit(c, Task::LSS, "{macs_per_cycle: 1}");
  return c;
}

/// One frame whose tasks take: FD a, IF b (each image), FC c (c even), MO m, DC d, LSS 9e
/// cycles; DR streams the level-0 image given to simulate_frontend at 1 pixel a cycle.
trace::FrameTrace frame(std::int64_t id, std::int64_t a, std::int64_t b, std::int64_t c,
                        std::int64_t m, std::int64_t d, std::int64_t e) {
  trace::FrameTrace f;
  f.frame.frame_id = id;
  const auto row = [&](Task task, Image image) {
    trace::TaskRecord t;
    t.task = task;
    t.image = image;
    f.tasks.push_back(t);
    return &f.tasks.back();
  };
  for (Image image : {Image::Left, Image::Right}) {
    row(Task::FD, image)->pixels = a;  // no per_level rows: no halo
    row(Task::IF, image)->pixels = b;
  }
  row(Task::DC, Image::Left)->pixels = d;
  auto* lss = row(Task::LSS, Image::Left);
  lss->window_size = 1;
  lss->points = 0;
  lss->iterations = e;  // 1 * 9 * iterations / 1 mac: 9e cycles
  for (Image image : {Image::Left, Image::Right}) {
    auto* fc = row(Task::FC, image);
    fc->window_size = 1;  // 1 row + 1 test group = 2 cycles per descriptor
    fc->descriptors = c / 2;
  }
  row(Task::MO, Image::Stereo)->comparisons = m;
  auto* dr = row(Task::DR, Image::Stereo);
  dr->keypoints = dr->windows = 1;
  dr->window_size = 1;
  dr->search_range = 1;
  return f;
}

TEST(FrontendModel, OneFrameFollowsTheCriticalPathOfTheTaskGraph) {
  // FD 100, IF 50, FC 10, MO 5, DR 400 (the image), DC 20, LSS 9*30 = 270.
  const std::vector<trace::FrameTrace> frames = {frame(0, 100, 50, 10, 5, 20, 30)};
  const FrontendSimResult r = simulate_frontend(frames, 400, unit_config());
  ASSERT_EQ(r.frames.size(), 1u);
  const FrontendFrameTiming& t = r.frames[0];
  // FD L [0,100], FD R [100,200] (one engine), FC L [100,110], FC R [200,210], MO [210,215],
  // DR [215,615]; IF L [0,50], DC [50,70], LSS [70,340]. End: 615 cycles = 6.15 us.
  EXPECT_EQ(t.end, sim::ns(6150));
  EXPECT_DOUBLE_EQ(t.latency_ms, 6.15e-3);
  EXPECT_DOUBLE_EQ(t.fe_ms, 2.10e-3);
  EXPECT_DOUBLE_EQ(t.sm_ms, 4.05e-3);
  EXPECT_DOUBLE_EQ(t.tm_ms, 2.90e-3);
  // TM off the critical path: with LSS longer than the rest, it decides the end.
  const FrontendSimResult tm =
      simulate_frontend({frame(0, 100, 50, 10, 5, 20, 100)}, 400, unit_config());
  EXPECT_EQ(tm.frames[0].end, sim::ns(10 * (50 + 20 + 900)));
}

TEST(FrontendModel, TaskRowsInAnyOrderGiveTheSameSchedule) {
  // The model finds each (task, image) row wherever the trace puts it: rows reversed, the same
  // 615 cycles and FE/SM/TM spans as above.
  trace::FrameTrace reversed = frame(0, 100, 50, 10, 5, 20, 30);
  std::reverse(reversed.tasks.begin(), reversed.tasks.end());
  const FrontendSimResult r = simulate_frontend({reversed}, 400, unit_config());
  ASSERT_EQ(r.frames.size(), 1u);
  EXPECT_EQ(r.frames[0].end, sim::ns(6150));
  EXPECT_DOUBLE_EQ(r.frames[0].fe_ms, 2.10e-3);
  EXPECT_DOUBLE_EQ(r.frames[0].sm_ms, 4.05e-3);
  EXPECT_DOUBLE_EQ(r.frames[0].tm_ms, 2.90e-3);
  // Each row's span is its own task's: DR (the last row now) ran [215, 615] cycles.
  EXPECT_EQ(r.frames[0].tasks.front().task, Task::DR);
  EXPECT_EQ(r.frames[0].tasks.front().start, sim::ns(2150));
  EXPECT_EQ(r.frames[0].tasks.front().end, sim::ns(6150));
}

TEST(FrontendModel, PipeliningOverlapsFeatureExtractionWithStereoMatching) {
  std::vector<trace::FrameTrace> frames;
  for (int i = 0; i < 20; ++i) frames.push_back(frame(i, 100, 50, 10, 5, 20, 30));
  FrontendConfig c = unit_config();
  c.pipeline_fe_sm = false;
  const FrontendSimResult serial = simulate_frontend(frames, 400, c);
  // One frame buffer: frames follow each other, period = latency = 615 cycles.
  EXPECT_NEAR(serial.throughput_fps, 1e8 / 615, 1e-6);
  for (const auto& t : serial.frames) EXPECT_DOUBLE_EQ(t.latency_ms, 6.15e-3);
  c.pipeline_fe_sm = true;
  const FrontendSimResult piped = simulate_frontend(frames, 400, c);
  // Two buffers: the bottleneck unit (DR, 400 cycles a frame) sets the period.
  EXPECT_NEAR(piped.throughput_fps, 1e8 / 400, 1e-6);
  EXPECT_GT(piped.throughput_fps, serial.throughput_fps);
  // DR busy all the time in steady state.
  for (const auto& [unit, u] : piped.utilization) {
    if (unit == "DR") {
      EXPECT_GT(u, 0.95);
    }
    EXPECT_LE(u, 1.0 + 1e-12) << unit;
  }
}

TEST(FrontendModel, CameraRateLeavesTheAcceleratorIdleBetweenFrames) {
  std::vector<trace::FrameTrace> frames;
  for (int i = 0; i < 5; ++i) frames.push_back(frame(i, 100, 50, 10, 5, 20, 30));
  FrontendConfig c = unit_config();
  c.frame_interval_ms = 0.01;  // 1000 cycles, longer than a frame's 615
  const FrontendSimResult r = simulate_frontend(frames, 400, c);
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    EXPECT_EQ(r.frames[i].arrival, sim::us(10) * i);
    EXPECT_EQ(r.frames[i].start, r.frames[i].arrival);
    EXPECT_DOUBLE_EQ(r.frames[i].response_ms, 6.15e-3);
  }
  EXPECT_NEAR(r.throughput_fps, 1e5, 1e-6);  // the camera's rate
}

TEST(FrontendModel, WritesATimelineOfTheChosenFrames) {
  std::vector<trace::FrameTrace> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(frame(i, 100, 50, 10, 5, 20, 30));
  const edx::testing::TempDir dir;
  const auto path = dir.path() / "timeline.json";
  FrontendSimOptions options;
  options.timeline = path;
  options.timeline_first = 1;
  options.timeline_count = 2;
  simulate_frontend(frames, 400, unit_config(), options);
  std::ifstream in(path);
  const nlohmann::json doc = nlohmann::json::parse(in);
  int spans = 0;
  for (const auto& e : doc["traceEvents"]) {
    if (e["ph"] == "X") ++spans;
  }
  EXPECT_EQ(spans, 2 * 11);  // ten tasks and the frame span, for frames 1 and 2
  std::filesystem::remove(path);
}

TEST(FrontendModel, AFrameWithoutTaskRowsIsAnError) {
  trace::FrameTrace empty;
  empty.frame.frame_id = 7;
  try {
    simulate_frontend({empty}, 100, unit_config());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("frame 7"));
  }
  trace::FrameTrace partial = frame(3, 1, 1, 2, 1, 1, 1);
  partial.tasks.pop_back();  // no DR
  EXPECT_THROW(simulate_frontend({partial}, 100, unit_config()), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
