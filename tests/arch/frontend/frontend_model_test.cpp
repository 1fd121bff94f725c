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

/// Frames through a FrontendAccelerator (a process per frame holding a frame buffer, as
/// simulate_frontend runs them) with the event log on or off: on, no wait may skip its event, so
/// every frame runs its task processes; off, a frame that can run alone takes the closed form.
struct AcceleratorRun {
  std::vector<FrontendFrameTiming> frames;
  std::vector<double> busy, queue;  ///< per unit: the integrals
  std::vector<std::uint64_t> acquisitions;
  sim::Time end = 0;
  std::uint64_t events = 0;
};
AcceleratorRun run_accelerator(const std::vector<trace::FrameTrace>& frames,
                               const FrontendConfig& config, sim::Time period, bool log) {
  sim::Simulator sim;
  if (log) sim.enable_event_log();
  FrontendAccelerator accelerator(sim, config);
  AcceleratorRun r;
  for (const trace::FrameTrace& f : frames) {
    r.frames.push_back(prepare_frontend_frame(f, 400, config, {}));
  }
  auto frame = [&](FrontendFrameTiming& t, sim::Lease buffer) -> sim::Process {
    co_await accelerator.run_frame(t, nullptr);
    buffer.release();
  };
  auto dispatch = [&]() -> sim::Process {
    for (std::size_t f = 0; f < r.frames.size(); ++f) {
      sim::Lease buffer = co_await accelerator.frame_buffers().acquire();
      if (period * f > sim.now()) co_await sim.delay_until(period * f);
      sim.spawn(frame(r.frames[f], std::move(buffer)));
    }
  };
  sim.spawn(dispatch());
  sim.run();
  for (Task task : trace::kTasks) {
    r.busy.push_back(accelerator.unit(task).busy().integral());
    r.queue.push_back(accelerator.unit(task).queue().integral());
    r.acquisitions.push_back(accelerator.unit(task).acquisitions());
  }
  r.end = sim.now();
  r.events = sim.events_processed();
  return r;
}

void expect_same_run(const AcceleratorRun& a, const AcceleratorRun& b) {
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t f = 0; f < a.frames.size(); ++f) {
    EXPECT_EQ(a.frames[f].transfer_start, b.frames[f].transfer_start) << f;
    EXPECT_EQ(a.frames[f].end, b.frames[f].end) << f;
    for (std::size_t i = 0; i < a.frames[f].tasks.size(); ++i) {
      EXPECT_EQ(a.frames[f].tasks[i].start, b.frames[f].tasks[i].start) << f << " " << i;
      EXPECT_EQ(a.frames[f].tasks[i].end, b.frames[f].tasks[i].end) << f << " " << i;
    }
  }
  EXPECT_EQ(a.busy, b.busy);
  EXPECT_EQ(a.queue, b.queue);
  EXPECT_EQ(a.acquisitions, b.acquisitions);
  EXPECT_EQ(a.end, b.end);
}

TEST(FrontendModel, AFrameAloneInClosedFormEqualsItsTaskProcesses) {
  // Frames of different shapes, one buffer; FC of the right image asks for its unit after the
  // left one's end (FD 100 > FC 10) or before it (FD 5 < FC 40: it waits, handed the unit).
  std::vector<trace::FrameTrace> frames = {
      frame(0, 100, 50, 10, 5, 20, 30), frame(1, 5, 50, 40, 5, 20, 30), frame(2, 7, 3, 2, 9, 1, 1)};
  FrontendConfig c = unit_config();
  c.pipeline_fe_sm = false;
  // The units on clocks of their own (150 and 333 MHz: starts wait for their edges).
  c.units[static_cast<std::size_t>(Task::FC)].clock_mhz = 150;
  c.units[static_cast<std::size_t>(Task::DR)].clock_mhz = 333;
  const AcceleratorRun des = run_accelerator(frames, c, 0, true);
  const AcceleratorRun closed = run_accelerator(frames, c, 0, false);
  expect_same_run(des, closed);
  // By hand: FD L of frame 0 (100 MHz) ran [0, 100] cycles; DR of frame 0 (333 MHz) starts on
  // its first edge at or after MO's end and ends 400 of its cycles later.
  EXPECT_EQ(closed.frames[0].tasks[0].end, sim::ns(1000));
  const TaskSpan& dr = closed.frames[0].tasks.back();
  ASSERT_EQ(dr.task, Task::DR);
  const sim::ClockDomain dr_clock("DR", 333);
  EXPECT_EQ(dr.start, dr_clock.next_edge(closed.frames[0].tasks[8].end));  // MO's end
  EXPECT_EQ(dr.end, dr_clock.time_of_cycles(dr_clock.cycles_in(dr.start) + 400));
  // No task process ran: a frame's events are its process's (start, clock edge), not ten more.
  EXPECT_LT(closed.events, des.events / 3);
  // FC of the right image asking at the very end of the left one's (FD 10 = FC 10 cycles on one
  // clock: both at 20): the unit is released, then taken again (no wait), as the processes do.
  const FrontendConfig same_clock = unit_config();
  const std::vector<trace::FrameTrace> tie = {frame(0, 10, 50, 10, 5, 20, 30)};
  const AcceleratorRun tie_des = run_accelerator(tie, same_clock, 0, true);
  const AcceleratorRun tie_closed = run_accelerator(tie, same_clock, 0, false);
  expect_same_run(tie_des, tie_closed);
  EXPECT_EQ(tie_closed.frames[0].tasks[6].end, tie_closed.frames[0].tasks[7].start);  // FC L, R
  EXPECT_EQ(tie_closed.queue[static_cast<std::size_t>(Task::FC)], 0.0);
  EXPECT_LT(tie_closed.events, tie_des.events);
  // Two buffers: frames overlap (the task processes), the same as with the log on.
  c.pipeline_fe_sm = true;
  expect_same_run(run_accelerator(frames, c, 0, true), run_accelerator(frames, c, 0, false));
  // IF of the right image outlasting DR and LSS: the task processes (it is still running when
  // the frame goes on), and the same as with the log on.
  c.pipeline_fe_sm = false;
  const std::vector<trace::FrameTrace> long_if = {frame(0, 10, 5000, 2, 1, 1, 1),
                                                  frame(1, 10, 50, 2, 1, 1, 1)};
  expect_same_run(run_accelerator(long_if, c, sim::us(100), true),
                  run_accelerator(long_if, c, sim::us(100), false));
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
