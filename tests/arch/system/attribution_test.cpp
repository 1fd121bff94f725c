// Critical-path attribution of the whole-system DES (docs/MODEL.md, "Critical-path
// attribution"): every frame's causes add up to its latency (1e-9 relative) on the golden mixes
// of both platforms, with and without contention; and hand-built contention cases name their
// cause with hand-computed figures: host cores oversubscribed, a sensor faster than the
// pipeline, a saturated link, a slow backend unit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "arch/results/causes.hpp"
#include "arch/system/system_des.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/system/hand_tasks.hpp"
#include "tests/arch/system/host_frames.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

/// Frame f's cause `name` in ms (0 when the run has no such cause).
double cause_ms(const SystemRun& r, std::size_t f, const std::string& name) {
  const auto it = std::find(r.causes.begin(), r.causes.end(), name);
  if (it == r.causes.end()) return 0.0;
  return sim::to_ms(r.cause_ps[f * r.causes.size() + std::size_t(it - r.causes.begin())]);
}

/// Σ of frame f's causes, ps.
sim::Time frame_sum(const SystemRun& r, std::size_t f) {
  sim::Time sum = 0;
  for (std::size_t c = 0; c < r.causes.size(); ++c) sum += r.cause_ps[f * r.causes.size() + c];
  return sum;
}

TEST(Attribution, HostCoresOversubscribed) {
  // One core for the frontend and backend threads, fe 3 ms, be 5 ms, back to back
  // (SystemDes.OneCoreSerializesTheThreads): FE f0 0-3, FE f1 3-6, BE f0 asks at 3 and runs
  // 6-11, FE f2 asks at 6 and runs 11-14, BE f1 asks at 11 and runs 14-19, FE f3 asks at 14 and
  // runs 19-22, BE f2 asks at 19 and runs 22-27.
  const SystemRun r = run_baseline(host_frames(4, 3, 5), SystemConfig{}, 1);
  // Frame 0: run 3 + 5, waits 3 for the core.
  EXPECT_NEAR(cause_ms(r, 0, "host.run"), 8.0, 1e-9);
  EXPECT_NEAR(cause_ms(r, 0, "host.wait"), 3.0, 1e-9);
  // Frame 1 (3-19): run 3 + 5, results wait 6-11, core wait 11-14.
  EXPECT_NEAR(cause_ms(r, 1, "queue.results.wait"), 5.0, 1e-9);
  EXPECT_NEAR(cause_ms(r, 1, "host.wait"), 3.0, 1e-9);
  // Frame 2 (6-27): core wait 6-11, run 11-14, results wait 14-19, core wait 19-22, run 22-27.
  EXPECT_NEAR(cause_ms(r, 2, "host.wait"), 8.0, 1e-9);
  EXPECT_NEAR(cause_ms(r, 2, "queue.results.wait"), 5.0, 1e-9);
  EXPECT_NEAR(cause_ms(r, 2, "host.run"), 8.0, 1e-9);
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    EXPECT_EQ(frame_sum(r, f), r.frames[f].end - r.frames[f].arrival) << f;
  }
  // With a core per thread nothing waits for one.
  const SystemRun two = run_baseline(host_frames(4, 3, 5), SystemConfig{}, 2);
  for (std::size_t f = 0; f < two.frames.size(); ++f) {
    EXPECT_EQ(cause_ms(two, f, "host.wait"), 0.0) << f;
  }
}

TEST(Attribution, SensorFasterThanThePipeline) {
  // A camera at 1000 FPS (frame k arrives at k ms) and a frontend of 3 ms: frame k starts at 3k
  // and waits 2k ms in the camera queue; the backend (2 ms) keeps up: no results wait.
  SystemConfig system;
  system.sensor_fps = 1000;
  system.queue_depth = 100;
  const SystemRun r = run_baseline(host_frames(10, 3, 2), system, 2);
  for (std::size_t k = 0; k < 10; ++k) {
    EXPECT_NEAR(cause_ms(r, k, "sensor.wait"), 2.0 * double(k), 1e-9) << k;
    EXPECT_NEAR(cause_ms(r, k, "host.run"), 5.0, 1e-9) << k;
    EXPECT_EQ(cause_ms(r, k, "queue.results.wait"), 0.0) << k;
    EXPECT_EQ(frame_sum(r, k), r.frames[k].end - r.frames[k].arrival) << k;
  }
}

TEST(Attribution, DroppedFramesKeepRowsOfZero) {
  // A camera at 800 FPS (frame k arrives at 1.25 k ms), a camera queue of one, a frontend of
  // 3 ms and a backend of 2 ms on cores of their own: the frontend takes a frame at 0, 3, 6, 9
  // and 12 ms; each backend ends 2 ms after the next take (its frontend's end). Dropping the
  // newest keeps frames 0, 1, 3, 5, 8 (started at 0, 3, 6, 9, 12: camera waits 0, 1.75, 2.25,
  // 2.75, 2 ms); dropping the oldest keeps 0, 2, 4, 7, 9 (waits 0, 0.5, 1, 0.25, 0.75 ms). The
  // last frame dropped (newest) or the dropped ones between taken ones (oldest): every row is
  // there, zero for a dropped frame, and a kept frame's adds up to its latency.
  SystemConfig system;
  system.sensor_fps = 800;
  system.queue_depth = 1;
  struct Case {
    DropPolicy drop;
    std::vector<std::size_t> kept;
    std::vector<double> camera_wait_ms;
  };
  for (const Case& c : {Case{DropPolicy::kNewest, {0, 1, 3, 5, 8}, {0, 1.75, 2.25, 2.75, 2}},
                        Case{DropPolicy::kOldest, {0, 2, 4, 7, 9}, {0, 0.5, 1, 0.25, 0.75}}}) {
    system.drop = c.drop;
    const SystemRun r = run_baseline(host_frames(10, 3, 2), system, 2);
    ASSERT_EQ(r.cause_ps.size(), 10 * r.causes.size());
    EXPECT_EQ(r.dropped, 5u);
    for (std::size_t f = 0, k = 0; f < 10; ++f) {
      const bool kept = k < c.kept.size() && c.kept[k] == f;
      EXPECT_EQ(r.frames[f].dropped, !kept) << f;
      if (!kept) {
        EXPECT_EQ(frame_sum(r, f), 0) << f;
        for (std::size_t i = 0; i < r.causes.size(); ++i) {
          EXPECT_EQ(r.cause_ps[f * r.causes.size() + i], 0) << f << " " << r.causes[i];
        }
        continue;
      }
      EXPECT_NEAR(r.frames[f].start * 1e-9, 3.0 * double(k), 1e-6) << f;
      EXPECT_NEAR(cause_ms(r, f, "sensor.wait"), c.camera_wait_ms[k], 1e-6) << f;
      EXPECT_NEAR(cause_ms(r, f, "host.run"), 5.0, 1e-9) << f;
      EXPECT_EQ(frame_sum(r, f), r.frames[f].end - r.frames[f].arrival) << f;
      ++k;
    }
  }
}

/// A platform of round numbers (the system model tests'), `link` and `backend` its keys.
Platform platform(const std::string& link, const std::string& backend) {
  return Platform::parse(
      "name: test\n"
      "host: {times: measured, frontend_suite_ms: 10.0, backend_suite_ms: 8.0, active_w: 10.0,\n"
      "       idle_w: 1.0}\n"
      "backend: {spm_bytes: 67108864, " +
          backend +
          "}\n"
          "link: {latency_ns: 100, dma: {setup_ns: 100}, " +
          link +
          "}\n"
          "scheduler: {policy: always, training_fraction: 0}\n",
      "test.yaml");
}

std::vector<trace::FrameTrace> hand_frames(std::size_t n) {
  std::vector<trace::FrameTrace> frames;
  for (std::size_t f = 0; f < n; ++f) {
    frames.push_back(hand_frame());
    frames.back().frame.frame_id = static_cast<std::int64_t>(f);
    frames.back().frame.timestamp_ns = static_cast<std::int64_t>(f) * 1000;
  }
  return frames;
}

/// The accelerated variant's summary over all frames of a run ("isolated" or "streamed").
results::CauseSummary all_frames(const SystemResult& r, bool streamed) {
  const std::vector<results::CauseSummary> s = results::summarize_causes(
      streamed ? *r.accelerated.streamed_causes : *r.accelerated.isolated_causes);
  return s.back();
}

TEST(Attribution, SaturatedLinkIsTheBottleneck) {
  // 200 KB/s on one wire for both directions: the kernel's operands (3.3 KB), its results and
  // the frontend's transfer 1 (2.2 KB together) take 27 ms a frame against the host's 8 ms, and
  // frames contend for the wire.
  const Platform p = platform("bandwidth_gb_per_s: 0.0002, full_duplex: false",
                              "clock_mhz: 100, units: {gemm: {block: 2}}");
  const SystemResult r = simulate_system(p, hand_frames(6), hand_meta(), "hand");
  const results::CauseSummary isolated = all_frames(r, false);
  EXPECT_EQ(isolated.bottleneck().rfind("link.", 0), 0u) << isolated.to_json().dump();
  const results::CauseSummary streamed = all_frames(r, true);
  double link_wait = 0;
  for (const results::CauseShare& c : streamed.causes) {
    if (c.name.rfind("link.", 0) == 0 && c.name.ends_with(".wait")) link_wait += c.mean_ms;
  }
  EXPECT_GT(link_wait, 0.0) << streamed.to_json().dump();
}

TEST(Attribution, SlowBackendUnitIsTheBottleneck) {
  // A 10 kHz gemm: the projection's 300 cycles on one 2x2 array take 30 ms.
  const Platform p =
      platform("bandwidth_gb_per_s: 8", "clock_mhz: 0.01, units: {gemm: {block: 2}}");
  const SystemResult r = simulate_system(p, hand_frames(3), hand_meta(), "hand");
  const results::CauseSummary isolated = all_frames(r, false);
  EXPECT_EQ(isolated.bottleneck(), "backend.gemm") << isolated.to_json().dump();
  ASSERT_FALSE(isolated.causes.empty());
  EXPECT_EQ(isolated.causes.front().name, "backend.gemm.run");
  EXPECT_NEAR(isolated.causes.front().mean_ms, r.decisions.front().compute_ms, 1e-6);
}

// Issue 45: a camera rate inside its range that is too slow for the trace's frame count (the
// last frame would arrive past 2^64 ps) is an error naming the key, not sim_core's overflow.
TEST(SystemLimits, ACameraTooSlowForTheTracesFramesNamesItsRate) {
  Platform p = platform("bandwidth_gb_per_s: 8", "clock_mhz: 100, units: {gemm: {block: 2}}");
  p.system.sensor_fps = 0.001;  // 18 447 frames fit: frame f arrives at 1000 f s
  try {
    (void)simulate_system(p, hand_frames(18500), hand_meta(), "hand");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "system.sensor_fps");
    EXPECT_EQ(std::string(e.what()),
              "system.sensor_fps: 0.001 frames/s: the trace's 18500 frames would arrive over "
              "1.85e+07 s, beyond the 213 days simulated time holds");
  }
}

/// Every frame's causes add up to its latency: isolated to the frame's e2e_ms, streamed to
/// end − arrival (the stream's latency distribution).
void expect_exact_sums(const std::string& config, bool contention) {
  const trace::TraceReader reader(std::string(EDX_SOURCE_DIR) + "/tests/data/golden/golden_mix.db");
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  Platform p = Platform::load(std::string(EDX_SOURCE_DIR) + "/configs/" + config);
  p.system.contention = contention;
  const SystemResult r = simulate_system(p, frames, reader.meta(), "golden");
  for (const VariantResult* v : {&r.baseline, &r.accelerated}) {
    ASSERT_TRUE(v->isolated_causes && v->streamed_causes);
    const results::CauseTable& iso = *v->isolated_causes;
    ASSERT_EQ(iso.frames.size(), v->frames.size());
    for (std::size_t f = 0; f < iso.frames.size(); ++f) {
      double sum = 0;
      for (std::size_t c = 0; c < iso.causes.size(); ++c) sum += iso.at(f, c);
      const double e2e = v->frames[f].e2e_ms;
      EXPECT_LE(std::abs(sum - e2e), 1e-9 * e2e) << config << " " << v->variant << " " << f;
    }
    const results::CauseTable& str = *v->streamed_causes;
    double mean = 0;
    std::size_t processed = 0;
    for (std::size_t f = 0; f < str.frames.size(); ++f) {
      if (str.frames[f].dropped) continue;
      double sum = 0;
      for (std::size_t c = 0; c < str.causes.size(); ++c) sum += str.at(f, c);
      EXPECT_LE(std::abs(sum - str.frames[f].latency_ms), 1e-9 * str.frames[f].latency_ms);
      mean += sum;
      ++processed;
    }
    mean /= double(processed);
    const double expected = v->stream->latency_ms.mean;
    EXPECT_LE(std::abs(mean - expected), 1e-9 * expected) << config << " " << v->variant;
  }
}

TEST(Attribution, CausesAddUpToEveryFramesLatencyCar) {
  expect_exact_sums("edx_car.yaml", true);
  expect_exact_sums("edx_car.yaml", false);
}

TEST(Attribution, CausesAddUpToEveryFramesLatencyDrone) {
  expect_exact_sums("edx_drone.yaml", true);
  expect_exact_sums("edx_drone.yaml", false);
}

TEST(Attribution, SummaryRanksCausesAndResources) {
  // Two frames of one mode: causes a.run 1 and 3 ms, a.wait 1 and 1, b.run 2 and 0: mean
  // latency 4; resource a 3 ms (0.75), b 1 ms.
  results::CauseTable t;
  t.causes = {"a.run", "a.wait", "b.run"};
  t.frames = {{0, "vio", false, 4.0}, {1, "vio", false, 4.0}, {2, "vio", true, 0.0}};
  t.ms = {1, 1, 2, 3, 1, 0, 0, 0, 0};
  const std::vector<results::CauseSummary> s = results::summarize_causes(t);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].mode, "vio");
  EXPECT_EQ(s[1].mode, "all");
  EXPECT_EQ(s[1].frames, 2u);
  EXPECT_EQ(s[1].bottleneck(), "a");
  EXPECT_DOUBLE_EQ(s[1].resources[0].mean_ms, 3.0);
  EXPECT_DOUBLE_EQ(s[1].resources[0].share, 0.75);
  EXPECT_EQ(s[1].causes[0].name, "a.run");
  EXPECT_DOUBLE_EQ(s[1].causes[0].mean_ms, 2.0);
  // Back from the database rows: the same table.
  const std::vector<results::FrameRow> frames = {{"r", "accelerated", 0, "vio"},
                                                 {"r", "accelerated", 1, "vio"},
                                                 {"r", "accelerated", 2, "vio"}};
  const results::CauseTable back =
      results::cause_table_of(results::frame_causes_rows("r", "accelerated", "streamed", t), frames,
                              "accelerated", "streamed");
  EXPECT_EQ(results::causes_json(back), results::causes_json(t));
}

}  // namespace
}  // namespace edx::arch
