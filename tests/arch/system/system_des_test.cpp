// The whole-system DES (arch/system/system_des): hand-computed queueing, back-pressure, drops
// and core contention on hand-built frames; the backend split; and, without contention, the
// analytical model reproduced to 1e-9 on the golden traces of both platforms.
#include "arch/system/system_des.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "arch/host/frontend_graph.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/system/host_frames.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

double ms(sim::Time t) { return sim::to_ms(t); }

TEST(SystemDes, TwoCoresPipelineFrontendAndBackend) {
  // Back to back, fe 3 ms, be 5 ms: frontends end at 3, 6, 9, 12; backends run 3-8, 8-13,
  // 13-18, 18-23: FPS 3 / 15 ms = 200.
  const SystemRun r = run_baseline(host_frames(4, 3, 5), SystemConfig{}, 2);
  ASSERT_EQ(r.frames.size(), 4u);
  EXPECT_NEAR(ms(r.frames[3].end), 23.0, 1e-9);
  EXPECT_NEAR(r.fps, 200.0, 1e-6);
  EXPECT_NEAR(r.host_busy_ms, 32.0, 1e-9);
}

TEST(SystemDes, OneCoreSerializesTheThreads) {
  // One core, FIFO between the two threads: FE f0 0-3, FE f1 3-6 (the backend asked at 3,
  // after the frontend took the core again), BE f0 6-11, FE f2 11-14, BE f1 14-19, FE f3 19-22,
  // BE f2 22-27, BE f3 27-32: FPS 3 / (32 - 11) ms.
  const SystemRun r = run_baseline(host_frames(4, 3, 5), SystemConfig{}, 1);
  const std::vector<double> ends = {11, 19, 27, 32};
  for (std::size_t f = 0; f < 4; ++f) EXPECT_NEAR(ms(r.frames[f].end), ends[f], 1e-9) << f;
  EXPECT_NEAR(r.fps, 3e3 / 21.0, 1e-6);
  const auto cores = std::find_if(r.resources.begin(), r.resources.end(),
                                  [](const ResourceUse& u) { return u.name == "host.cores"; });
  ASSERT_NE(cores, r.resources.end());
  EXPECT_NEAR(cores->busy, 1.0, 1e-9);  // busy from 0 to 32 ms
}

TEST(SystemDes, IsolatedRunIsOneFrameAtATime) {
  const SystemRun r = run_baseline(host_frames(3, 3, 5), SystemConfig{}, 2, /*isolated=*/true);
  for (std::size_t f = 0; f < 3; ++f) {
    EXPECT_NEAR(ms(r.frames[f].start), 8.0 * double(f), 1e-9);
    EXPECT_NEAR(ms(r.frames[f].end - r.frames[f].start), 8.0, 1e-9);
  }
}

TEST(SystemDes, TheBaselineFrontendsChainsRunSideBySideOnTheCores) {
  // Stage 1: chains of 4, 3 and 2 ms; stage 2: 1 and 1 ms; stage 3: 0.5 ms. Isolated, two
  // cores: stage 1 takes 5 ms (4 on one core; 3 then 2 on the other), stage 2 1 ms, stage 3
  // 0.5 ms: 6.5 ms, as frontend_latency_ms says. One core: the sum, 11.5 ms.
  const StageChains chains = {{{4}, {3}, {2}}, {{1}, {1}}, {{0.5}}};
  std::vector<SystemFrameWork> work = host_frames(2, 11.5, 2);
  for (SystemFrameWork& w : work) w.frontend_host_chains = chains;
  for (int cores : {1, 2, 3}) {
    const SystemRun r = run_baseline(work, SystemConfig{}, cores, /*isolated=*/true);
    const double expected = frontend_latency_ms(chains, cores);
    for (const SystemFrameTiming& t : r.frames) {
      EXPECT_NEAR(ms(t.frontend_end - t.start), expected, 1e-9) << cores;
    }
    EXPECT_NEAR(r.host_busy_ms, 2 * (11.5 + 2), 1e-9) << cores;  // the work, not the latency
  }
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 1), 11.5);
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 2), 6.5);
  EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, 3), 5.5);
}

TEST(SystemDes, TheCoprocessorRunsOneChainsRowsAtATime) {
  // Stage 1: three chains all on the device (2, 3 and 1 ms): 6 ms one after another, whatever
  // the cores. Stage 2: a chain of 1 ms on a core then 2 ms on the device: 3 ms. The backend: 2 ms
  // on a core, then 1.5 ms on the device. The host is busy 1 + 2 ms of the frame.
  const StageChains chains = {{{0, 2}, {0, 3}, {0, 1}}, {{1, 2}}};
  std::vector<SystemFrameWork> work = host_frames(1, 9, 2);
  work[0].frontend_host_chains = chains;
  work[0].backend_device_ms = 1.5;
  for (int cores : {1, 4}) {
    EXPECT_DOUBLE_EQ(frontend_latency_ms(chains, cores), 9.0) << cores;
    const SystemRun r = run_baseline(work, SystemConfig{}, cores, /*isolated=*/true);
    const SystemFrameTiming& t = r.frames.at(0);
    EXPECT_NEAR(ms(t.frontend_end - t.start), 9.0, 1e-9) << cores;
    EXPECT_NEAR(ms(t.end - t.backend_start), 3.5, 1e-9) << cores;
    EXPECT_NEAR(r.host_busy_ms, 3.0, 1e-9) << cores;
  }
}

/// Camera at 200 FPS (every 5 ms), fe 3 ms, be 11.5 ms, both queues of depth 1.
SystemConfig camera(DropPolicy drop) {
  SystemConfig c;
  c.sensor_fps = 200;
  c.queue_depth = 1;
  c.results_queue_depth = 1;
  c.drop = drop;
  return c;
}

TEST(SystemDes, BackPressureAndDropNewest) {
  // f0: FE 0-3, BE 3-14.5. f1 (5): FE 5-8, queued, BE 14.5-26. f2 (10): FE 10-13, the results
  // queue is full until 14.5 (the frontend thread waits), BE 26-37.5. f3 (15): FE 15-18, waits
  // until 26, BE 37.5-49. f4 (20) waits in the camera queue until the frontend thread is free
  // at 26: FE 26-29, waits until 37.5, BE 49-60.5. f5 (25) finds the camera queue full: dropped.
  const SystemRun r = run_baseline(host_frames(6, 3, 11.5), camera(DropPolicy::kNewest), 2);
  EXPECT_EQ(r.dropped, 1u);
  EXPECT_TRUE(r.frames[5].dropped);
  const std::vector<double> latency = {14.5, 21, 27.5, 34, 40.5};
  for (std::size_t f = 0; f < 5; ++f) {
    EXPECT_FALSE(r.frames[f].dropped);
    EXPECT_NEAR(ms(r.frames[f].end - r.frames[f].arrival), latency[f], 1e-9) << f;
  }
  EXPECT_NEAR(ms(r.frames[4].start), 26.0, 1e-9);
}

TEST(SystemDes, DropOldestKeepsTheFreshFrame) {
  // As above, but f5's arrival drops f4 (waiting since 20); f5 runs FE 26-29, BE 49-60.5.
  const SystemRun r = run_baseline(host_frames(6, 3, 11.5), camera(DropPolicy::kOldest), 2);
  EXPECT_EQ(r.dropped, 1u);
  EXPECT_TRUE(r.frames[4].dropped);
  EXPECT_NEAR(ms(r.frames[5].end - r.frames[5].arrival), 35.5, 1e-9);
}

TEST(SystemDes, DropNoneQueuesEverything) {
  const SystemRun r = run_baseline(host_frames(6, 3, 11.5), camera(DropPolicy::kNone), 2);
  EXPECT_EQ(r.dropped, 0u);
  // The backend is the bottleneck: it runs back to back from 3 ms, 11.5 ms a frame.
  EXPECT_NEAR(ms(r.frames[5].end), 3 + 6 * 11.5, 1e-9);
}

TEST(SystemDes, SplitBackendSpreadsHostTimeOverTheGaps) {
  // Backend 10 ms; kernels: host-only 1 ms, offloaded 2 ms, host-only 3 ms. Outside the kernels:
  // 10 - 6 = 4 ms, 2 ms in each of the two gaps: [1 + 2] offload [3 + 2].
  trace::FrameTrace frame;
  frame.kernels.resize(3);
  const std::vector<BackendStep> steps = split_backend(frame, 10, {1, 2, 3}, {false, true, false});
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_DOUBLE_EQ(steps[0].host_ms, 3.0);
  EXPECT_EQ(steps[1].offload, 0);
  EXPECT_DOUBLE_EQ(steps[2].host_ms, 5.0);
  // Kernels adding up to more than the backend: the host steps are scaled to backend − offloaded.
  const std::vector<BackendStep> scaled = split_backend(frame, 5, {1, 2, 3}, {false, true, false});
  ASSERT_EQ(scaled.size(), 3u);
  EXPECT_DOUBLE_EQ(scaled[0].host_ms + scaled[2].host_ms, 3.0);
  EXPECT_DOUBLE_EQ(scaled[0].host_ms, 0.75);
}

TEST(SystemDes, ConfigErrorsNameTheKey) {
  try {
    Platform::parse("name: x\nsystem: {drop: sometimes}\n", "p.yaml");
    FAIL() << "accepted drop: sometimes";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("p.yaml:2: system.drop: expected oldest, newest or none"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Platform::parse("name: x\nsystem: {queue_depth: 0}\n", "p.yaml"),
               std::runtime_error);
  EXPECT_THROW(Platform::parse("name: x\nsystem: {sensor_fps: -1}\n", "p.yaml"),
               std::runtime_error);
  EXPECT_THROW(Platform::parse("name: x\nhost: {cores: 0}\n", "p.yaml"), std::runtime_error);
}

/// Equal to 1e-9 relative, or within 5 ps for short spans: the DES's unit is 1 ps and each of a
/// frame's steps (host work, transfers, kernels) is rounded to it.
bool close(double a_ms, double b_ms) {
  return std::abs(a_ms - b_ms) <= std::max(1e-9 * std::abs(b_ms), 5e-9);
}

/// Without contention the DES is the analytical model: per frame and in throughput. `policy`
/// replaces the config's offload policy when given (the check needs offloaded kernels).
void expect_des_equals_analytical(const std::string& config,
                                  std::optional<OffloadPolicy> policy = std::nullopt) {
  const trace::TraceReader reader(std::string(EDX_SOURCE_DIR) + "/tests/data/golden/golden_mix.db");
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  Platform platform = Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/" + config);
  platform.system.contention = false;
  if (policy) platform.scheduler.policy = *policy;
  SystemSimOptions des, analytical;
  analytical.model = SystemModelKind::kAnalytical;
  const SystemResult a = simulate_system(platform, frames, reader.meta(), "golden", analytical);
  const SystemResult d = simulate_system(platform, frames, reader.meta(), "golden", des);
  std::size_t offloaded = 0;
  for (const KernelDecision& k : d.decisions) offloaded += k.offloaded ? 1 : 0;
  EXPECT_GT(offloaded, 0u) << config << ": the check needs offloaded kernels";
  for (const auto& [va, vd] :
       {std::pair{&a.baseline, &d.baseline}, {&a.accelerated, &d.accelerated}}) {
    ASSERT_EQ(va->frames.size(), vd->frames.size());
    for (std::size_t f = 0; f < va->frames.size(); ++f) {
      const FrameResult& x = va->frames[f];
      const FrameResult& y = vd->frames[f];
      EXPECT_TRUE(close(y.frontend_ms, x.frontend_ms))
          << config << " " << va->variant << " frame " << f << ": " << y.frontend_ms << " vs "
          << x.frontend_ms;
      EXPECT_TRUE(close(y.backend_ms, x.backend_ms))
          << config << " " << va->variant << " frame " << f << ": " << y.backend_ms << " vs "
          << x.backend_ms;
      EXPECT_TRUE(close(y.e2e_ms, x.e2e_ms)) << config << " " << va->variant << " frame " << f;
      EXPECT_TRUE(close(y.energy.total_j, x.energy.total_j)) << config << " frame " << f;
    }
    EXPECT_TRUE(close(vd->fps_without_pipelining, va->fps_without_pipelining)) << config;
    EXPECT_TRUE(close(vd->fps_with_pipelining, va->fps_with_pipelining))
        << config << " " << va->variant << ": " << vd->fps_with_pipelining << " vs "
        << va->fps_with_pipelining;
  }
}

TEST(SystemDes, WithoutContentionEqualsTheAnalyticalModelCar) {
  expect_des_equals_analytical("edx_car.yaml");
}

// On the small golden mix the TX1 host beats Edx-Drone's matrix units on every kernel the
// regression policy weighs, so the drone's check offloads every accelerable kernel.
TEST(SystemDes, WithoutContentionEqualsTheAnalyticalModelDrone) {
  expect_des_equals_analytical("edx_drone.yaml", OffloadPolicy::kAlways);
}

}  // namespace
}  // namespace edx::arch
