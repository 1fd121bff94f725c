// The whole-system model on hand-built traces whose backend times, offload decisions, FPS and
// energies are computed by hand; the results database's contents and its replace-on-rerun rule.
#include "arch/system/system_model.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "arch/results/results_db.hpp"
#include "arch/system/result_rows.hpp"
#include "tests/arch/backend/backend_test_support.hpp"
#include "tests/arch/system/hand_tasks.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

using trace::BackendMode;

/// Backend 100 MHz, 2x2 array, 64 MiB SPM; link 1 GB/s with 100 ns setup and latency and one
/// chunk (a B-byte transfer takes B + 200 ns); frontend and backend host scales 1 and 2 (the
/// host's suite times over kMeta's: 10/10 ms and 8/4 ms); power with round numbers.
/// `backend_keys`: more keys of `backend:` ("precision: fp32, ").
Platform test_platform(const std::string& policy, const std::string& backend_keys = "") {
  return Platform::parse(
      "name: test\n"
      "host: {times: measured, frontend_suite_ms: 10.0, backend_suite_ms: 8.0, active_w: 10.0,\n"
      "       idle_w: 1.0}\n"
      "backend: {" +
          backend_keys +
          "clock_mhz: 100, spm_bytes: 67108864, units: {gemm: {block: 2}}}\n"
          "link:\n  bandwidth_gb_per_s: 1.0\n  latency_ns: 100\n  pj_per_byte: 1.0\n"
          "  dma: {setup_ns: 100, chunk_bytes: 4194304, max_outstanding: 1}\n"
          "memory: {pj_per_byte: 1.0}\n"
          "power: {fpga_static_w: 1.0, int8_op_pj: 1.0,\n"
          "        single_mac_pj: 1.0, double_mac_pj: 10.0, fpga_energy_factor: 1.0,\n"
          "        dram_pj_per_byte: 0.0}\n"
          "scheduler: {policy: " +
          policy + ", training_fraction: 0.25}\n",
      "test.yaml");
}

/// `backend` (kind fpga_matrix_units) with an SPM of `bytes`.
std::shared_ptr<const OffloadAccelerator> with_spm(const OffloadAccelerator& backend,
                                                   std::int64_t bytes) {
  BackendConfig config = testing::fpga_config(backend);
  config.spm_bytes = bytes;
  return fpga_matrix_units(config);
}

trace::FrameTrace frame(std::int64_t id, BackendMode mode, std::int64_t backend_ns) {
  trace::FrameTrace f;
  f.frame.frame_id = id;
  f.frame.timestamp_ns = 1000 + id;
  f.frame.sequence = "test";
  f.frame.mode = mode;
  f.frame.frontend_host_ns = 3'000'000;  // 3 ms
  f.frame.backend_host_ns = backend_ns;
  f.tasks = hand_task_rows();
  return f;
}

trace::KernelRecord projection(std::int64_t points, std::int64_t host_ns) {
  trace::KernelRecord k;
  k.kernel = "projection";
  k.accelerable = true;
  k.host_ns = host_ns;
  k.m = points;
  k.ops = {trace::OpRecord{trace::Op::Gemm, 3, points, 4, 0, 0}};
  return k;
}

trace::KernelRecord host_only(std::int64_t host_ns) {
  trace::KernelRecord k;
  k.kernel = "tracking";
  k.host_ns = host_ns;
  return k;
}

/// Frame 0 (registration): backend 10 ms of which projection of 100 points 6 ms and tracking
/// 4 ms. Frame 1 (registration): backend 20 ms, projection of 100 000 points in 1 µs (faster on
/// the host). Frame 2 (slam): backend 5 ms, no accelerable kernel.
std::vector<trace::FrameTrace> three_frames() {
  std::vector<trace::FrameTrace> frames = {frame(0, BackendMode::Registration, 10'000'000),
                                           frame(1, BackendMode::Registration, 20'000'000),
                                           frame(2, BackendMode::Slam, 5'000'000)};
  frames[0].kernels = {projection(100, 6'000'000), host_only(4'000'000)};
  frames[1].kernels = {projection(100'000, 1'000)};
  return frames;
}

const trace::TraceMeta kMeta = {
    {"resolution", "40x25"},
    {"dataset", "hand"},
    {"precision", "fp64"},
    {"host_speed", R"({"suite": 1, "frontend_ms": 10.0, "backend_ms": 4.0, "samples": 1})"}};

// Projection of M points: gemm 3 x M x 4 on the 2x2 array: ⌈3/2⌉·⌈M/2⌉ tiles x (4 + 2·2)
// cycles at 100 MHz. Inputs (12 + 4M)·8 B, results 2M·8 B, each B + 200 ns on the link.
constexpr double kCompute0Ms = 2 * 50 * 8 / 100e6 * 1e3;                         // 0.008 ms
constexpr double kTransfer0Ms = ((3296 + 200) + (1600 + 200)) * 1e-6;            // 0.005296 ms
constexpr double kCompute1Ms = 2 * 50'000 * 8 / 100e6 * 1e3;                     // 8 ms
constexpr double kTransfer1Ms = ((3'200'096 + 200) + (1'600'000 + 200)) * 1e-6;  // 4.800496 ms

TEST(SystemModel, OracleOffloadsOnlyWhereTheAcceleratorIsFaster) {
  const SystemResult r = simulate_system(test_platform("oracle"), three_frames(), kMeta, "t.db");
  ASSERT_EQ(r.decisions.size(), 2u);
  EXPECT_NEAR(r.decisions[0].compute_ms, kCompute0Ms, 1e-12);
  EXPECT_NEAR(r.decisions[0].transfer_ms, kTransfer0Ms, 1e-9);
  EXPECT_NEAR(r.decisions[0].host_ms, 12.0, 1e-12);  // 6 ms x 2
  EXPECT_TRUE(r.decisions[0].offloaded);
  EXPECT_NEAR(r.decisions[1].accel_ms, kCompute1Ms + kTransfer1Ms, 1e-9);
  EXPECT_NEAR(r.decisions[1].host_ms, 0.002, 1e-12);
  EXPECT_FALSE(r.decisions[1].offloaded);

  // Baseline: FE 3 ms, BE = 2 x backend host time.
  const auto& b = r.baseline.frames;
  EXPECT_NEAR(b[0].e2e_ms, 23.0, 1e-9);
  EXPECT_NEAR(b[1].e2e_ms, 43.0, 1e-9);
  EXPECT_NEAR(b[2].e2e_ms, 13.0, 1e-9);
  // 3 frames in 79 ms; pipelined: b_end = 23, max(6, 23) + 40 = 63, max(9, 63) + 10 = 73.
  EXPECT_NEAR(r.baseline.fps_without_pipelining, 3e3 / 79.0, 1e-9);
  EXPECT_NEAR(r.baseline.fps_with_pipelining, 2e3 / (73.0 - 23.0), 1e-9);
  // Energy: no FPGA, host active all frame: 10 W x e2e.
  EXPECT_NEAR(b[0].energy.total_j, 0.23, 1e-12);
  EXPECT_NEAR(r.baseline.modes.at("registration").energy_j.mean, (0.23 + 0.43) / 2, 1e-12);

  // Accelerated: frame 0's projection replaced by its accelerator time.
  const auto& a = r.accelerated.frames;
  const double be0 = 20.0 - 12.0 + kCompute0Ms + kTransfer0Ms;
  EXPECT_NEAR(a[0].backend_ms, be0 + 5e-6, 5e-6);  // + up to one cycle to the backend clock edge
  EXPECT_NEAR(a[1].backend_ms, 40.0, 1e-9);
  EXPECT_NEAR(a[2].backend_ms, 10.0, 1e-9);
  for (int f = 0; f < 3; ++f) {
    EXPECT_GT(a[f].frontend_ms, 0);
    EXPECT_NEAR(a[f].frontend_ms, r.frontend.frame_accel_ms[f], 5e-9);  // ps rounding
    EXPECT_NEAR(a[f].e2e_ms, a[f].frontend_ms + a[f].backend_ms, 1e-12);
  }
  EXPECT_EQ(a[0].offloaded, 1);
  EXPECT_EQ(a[1].offloaded, 0);
  // Frame 0's energy: static 1 W x t, host 10 W x 8 ms + 1 W x (t − 8 ms), and in pJ:
  //   backend: 800 busy multiply cycles x 4 MACs x 10 pJ = 32 000; BRAM 5696 B (the gemm's
  //            operands (12 + 400 + 300) x 8); link 3296 + 1600 B;
  //   frontend: FD 2 x (65 x 1000 + 8 x 10) int8 ops, DC 1000 x (4 x 3 + 2 x 5) int8 ops,
  //            IF 2 x 1000 x 7² single MACs at 1 pJ; BRAM FD 2 x 2 x 1000 + DC 2 x 1000 B;
  //            link: transfer 1 = no features + 10 IMU samples x 56 B = 560 B.
  const double t = 1e-3 * a[0].e2e_ms;
  const double pj = 32000 + (5696 + 4896) + (130160 + 22000) + 98000 + 6000 + 560;
  const double expected = 1.0 * t + 10.0 * 0.008 + 1.0 * (t - 0.008) + 1e-12 * pj;
  EXPECT_EQ(r.frontend.frame_results_bytes[0], 560);
  EXPECT_NEAR(a[0].energy.total_j, expected, 1e-12);
  // Without pipelining: 3 frames over Σ e2e.
  EXPECT_NEAR(r.accelerated.fps_without_pipelining, 3e3 / (a[0].e2e_ms + a[1].e2e_ms + a[2].e2e_ms),
              1e-9);
  // Per mode.
  EXPECT_EQ(r.accelerated.modes.at("registration").frames, 2u);
  EXPECT_EQ(r.accelerated.modes.at("slam").frames, 1u);
  EXPECT_EQ(r.accelerated.modes.at("all").frames, 3u);
  EXPECT_NEAR(r.comparison()["slam"]["backend_speedup"].get<double>(), 1.0, 1e-12);
}

// An fp32 backend runs an fp32 trace: the same cycles, half the bytes a scalar on the link
// (inputs (12 + 4·100)·4 B, results 2·100·4 B, each + 200 ns). A trace of the other precision,
// or an fp32 trace on a platform offloading a kernel the backends compute in fp64 only, is
// refused in one line naming both.
TEST(SystemModel, Fp32BackendRunsOnlyAnFp32Trace) {
  trace::TraceMeta fp32 = kMeta;
  fp32["precision"] = "fp32";
  const SystemResult r =
      simulate_system(test_platform("oracle", "precision: fp32, "), three_frames(), fp32, "t.db");
  EXPECT_NEAR(r.decisions[0].compute_ms, kCompute0Ms, 1e-12);
  EXPECT_NEAR(r.decisions[0].transfer_ms, ((1648 + 200) + (800 + 200)) * 1e-6, 1e-9);
  EXPECT_THAT([&] { simulate_system(test_platform("oracle"), three_frames(), fp32, "t.db"); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  "t.db: the trace computed its backend kernels in fp32 (meta precision), but "
                  "platform test computes in fp64 (backend.precision); trace with --precision "
                  "fp64 or set backend.precision: fp32"));
  EXPECT_THAT(
      [&] {
        simulate_system(test_platform("oracle", "precision: fp32, "), three_frames(), kMeta, "t");
      },
      ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
          "the trace computed its backend kernels in fp64 (meta precision), but platform test "
          "computes in fp32")));
  Platform beyond = test_platform("oracle", "precision: fp32, ");
  beyond.scheduler.offload.push_back("schur_complement");
  EXPECT_THAT([&] { simulate_system(beyond, three_frames(), fp32, "t.db"); },
              ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
                  "t.db: platform test offloads schur_complement (scheduler.offload), which the "
                  "backends compute in fp64 only")));
}

TEST(SystemModel, NeverAndAlwaysPolicies) {
  const SystemResult never = simulate_system(test_platform("never"), three_frames(), kMeta, "t");
  EXPECT_NEAR(never.accelerated.frames[0].backend_ms, 20.0, 1e-9);
  EXPECT_EQ(never.accelerated.frames[0].offloaded, 0);
  const SystemResult always = simulate_system(test_platform("always"), three_frames(), kMeta, "t");
  // The DES (model des, contention on) starts a kernel on the backend clock's next edge: up to
  // one cycle (10 ns) after the analytical model's start.
  const double analytical = 40.0 - 0.002 + kCompute1Ms + kTransfer1Ms;
  EXPECT_GE(always.accelerated.frames[1].backend_ms, analytical - 1e-9);
  EXPECT_LE(always.accelerated.frames[1].backend_ms, analytical + 1e-5);
  EXPECT_TRUE(always.decisions[1].offloaded);
}

// Invocations of one shape (name, sizes, detail, ops without host times) share their plan and
// transfers; each keeps its own host time; an op of another size is another shape.
TEST(SystemModel, AStudysPreparedFramesAreWhatTheModelWouldMakeAndGiveTheSameResult) {
  // study_frontend prepares each frame's DES rows and frontend activity once (sweep points that
  // share the study share them); they equal what simulate_system makes without them, and the
  // results with and without them are the same to the last bit.
  const Platform p = test_platform("always");
  const std::vector<trace::FrameTrace> frames = three_frames();
  FrontendStudy study = study_frontend(p, frames, kMeta, "t.db");
  ASSERT_NE(study.prepared_frames, nullptr);
  ASSERT_EQ(study.prepared_frames->size(), frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) {
    SCOPED_TRACE(f);
    const FrontendStudy::PreparedFrame& prepared = (*study.prepared_frames)[f];
    const FrontendFrameTiming made =
        prepare_frontend_frame(frames[f], 40 * 25, p.frontend, p.transfers);
    EXPECT_EQ(prepared.timing.frame_id, made.frame_id);
    EXPECT_EQ(prepared.timing.transfer_bytes, made.transfer_bytes);
    ASSERT_EQ(prepared.timing.tasks.size(), made.tasks.size());
    for (std::size_t t = 0; t < made.tasks.size(); ++t) {
      EXPECT_EQ(prepared.timing.tasks[t].task, made.tasks[t].task);
      EXPECT_EQ(prepared.timing.tasks[t].image, made.tasks[t].image);
      EXPECT_EQ(prepared.timing.tasks[t].cycles, made.tasks[t].cycles);
    }
    std::array<cost::FrameActivity, 7> by_task;
    const cost::FrameActivity activity = frontend_activity(frames[f], p.frontend, &by_task);
    EXPECT_EQ(prepared.activity.to_json(), activity.to_json());
    for (std::size_t t = 0; t < by_task.size(); ++t) {
      EXPECT_EQ(prepared.task_activity[t].to_json(), by_task[t].to_json()) << t;
    }
  }
  const std::string with = simulate_system(p, frames, kMeta, "t.db", study).to_json().dump();
  study.prepared_frames = nullptr;
  const std::string without = simulate_system(p, frames, kMeta, "t.db", study).to_json().dump();
  EXPECT_EQ(with, without);
}

// A run's independent parts (the study's four, the DES's four runs) on 1, 2 or 4 threads give
// the same result and rows to the last bit, with and without the baseline's runs given; a study
// given the host times it would compute (a sweep's check made them) equals one computing them,
// and host times of another host are not taken.
TEST(SystemModel, ThreadsAndKnownHostTimesLeaveTheResultAsItIs) {
  const Platform p = test_platform("always");
  const std::vector<trace::FrameTrace> frames = three_frames();
  SystemSimOptions one;
  const SystemResult reference = simulate_system(p, frames, kMeta, "t.db", one);
  const std::string rows = export_run_rows(result_rows(reference, true)).dump();
  for (int threads : {2, 4}) {
    SystemSimOptions options;
    options.threads = threads;
    const SystemResult r = simulate_system(p, frames, kMeta, "t.db", options);
    EXPECT_EQ(r.to_json().dump(), reference.to_json().dump()) << threads;
    EXPECT_EQ(export_run_rows(result_rows(r, true)).dump(), rows) << threads;
  }
  const FrontendStudy computed = study_frontend(p, frames, kMeta, "t.db");
  KnownHostTimes known{component_json(*p.host).dump(),
                       std::make_shared<const PlatformHostTimes>(computed.host_times)};
  FrontendStudyOptions with_known;
  with_known.known = &known;
  with_known.threads = 2;
  EXPECT_EQ(study_frontend(p, frames, kMeta, "t.db", with_known).to_json().dump(),
            computed.to_json().dump());
  // Times of another host (every frame's frontend doubled) are not this host's: not taken.
  PlatformHostTimes other = computed.host_times;
  for (double& ms : other.frontend_ms) ms *= 2;
  known = {"{\"kind\": \"another\"}", std::make_shared<const PlatformHostTimes>(other)};
  EXPECT_EQ(study_frontend(p, frames, kMeta, "t.db", with_known).to_json().dump(),
            computed.to_json().dump());
  known.host_key = component_json(*p.host).dump();  // the same times under this host's key: taken
  EXPECT_NE(study_frontend(p, frames, kMeta, "t.db", with_known).to_json().dump(),
            computed.to_json().dump());
}

// A sweep's points read one shared study in place (named after the first point's platform):
// each run's summary and rows, frames included, are those of a run on its own copy of the
// study, to the last bit; the shared study is left as it was and the result holds none.
TEST(SystemModel, ARunOnASharedStudyEqualsOneOnItsOwnCopy) {
  const Platform first = test_platform("always");
  Platform p = first;
  p.name = "another";
  const std::vector<trace::FrameTrace> frames = three_frames();
  const auto shared =
      std::make_shared<const FrontendStudy>(study_frontend(first, frames, kMeta, "t.db"));
  const std::string study_before = shared->to_json().dump();
  const SystemResult own = simulate_system(p, frames, kMeta, "t.db", FrontendStudy(*shared));
  const SystemResult on_shared = simulate_system(p, frames, kMeta, "t.db", shared);
  EXPECT_EQ(own.frontend.platform, "another");
  EXPECT_EQ(on_shared.to_json().dump(), own.to_json().dump());
  EXPECT_EQ(export_run_rows(result_rows(on_shared, true)).dump(),
            export_run_rows(result_rows(own, true)).dump());
  EXPECT_EQ(on_shared.accelerated.frames.size(), 3u);
  EXPECT_TRUE(on_shared.frontend.frame_accel_ms.empty());
  EXPECT_EQ(shared->to_json().dump(), study_before);
  EXPECT_EQ(shared->platform, first.name);
  EXPECT_THROW(simulate_system(p, frames, kMeta, "t.db", std::shared_ptr<const FrontendStudy>()),
               std::logic_error);
}

// Frames of two modes interleaved (slam, registration, slam, registration, registration): each
// mode's summary holds its own frames only, "all" every frame, whatever the order they come in.
TEST(SystemModel, ModeSummariesGroupInterleavedModes) {
  const std::vector<trace::FrameTrace> frames = {
      frame(0, BackendMode::Slam, 5'000'000), frame(1, BackendMode::Registration, 10'000'000),
      frame(2, BackendMode::Slam, 7'000'000), frame(3, BackendMode::Registration, 20'000'000),
      frame(4, BackendMode::Registration, 30'000'000)};
  const SystemResult r = simulate_system(test_platform("always"), frames, kMeta, "t.db");
  for (const VariantResult* v : {&r.baseline, &r.accelerated}) {
    SCOPED_TRACE(v->variant);
    ASSERT_EQ(v->frames.size(), 5u);
    const auto& f = v->frames;
    EXPECT_EQ(v->modes.size(), 3u);
    EXPECT_EQ(v->modes.at("slam").frames, 2u);
    EXPECT_EQ(v->modes.at("registration").frames, 3u);
    EXPECT_EQ(v->modes.at("all").frames, 5u);
    EXPECT_NEAR(v->modes.at("slam").backend_ms.mean, (f[0].backend_ms + f[2].backend_ms) / 2,
                1e-12);
    EXPECT_NEAR(v->modes.at("registration").backend_ms.mean,
                (f[1].backend_ms + f[3].backend_ms + f[4].backend_ms) / 3, 1e-12);
    EXPECT_NEAR(v->modes.at("registration").backend_ms.max,
                std::max({f[1].backend_ms, f[3].backend_ms, f[4].backend_ms}), 1e-12);
  }
  // The baseline's backend is the trace's on a host of scale 2: 10, 14 ms (slam) and 20, 40,
  // 60 ms (registration).
  EXPECT_NEAR(r.baseline.modes.at("slam").backend_ms.mean, 12.0, 1e-9);
  EXPECT_NEAR(r.baseline.modes.at("registration").backend_ms.mean, 40.0, 1e-9);
}

TEST(SystemModel, InvocationsOfOneShapeShareTheirCostsOnly) {
  std::vector<trace::FrameTrace> frames = {frame(0, BackendMode::Registration, 10'000'000),
                                           frame(1, BackendMode::Registration, 10'000'000)};
  trace::KernelRecord wide = projection(100, 1'000'000);
  wide.ops[0].n = 200;  // gemm 3 x 200 x 4: ⌈3/2⌉·⌈200/2⌉ tiles x 8 cycles = 1600 cycles
  trace::KernelRecord again = projection(100, 2'000'000);
  again.ops[0].host_ns = 123;  // another op host time: the same shape
  frames[0].kernels = {projection(100, 6'000'000), wide};
  frames[1].kernels = {again};
  const SystemResult r = simulate_system(test_platform("always"), frames, kMeta, "t.db");
  ASSERT_EQ(r.decisions.size(), 3u);
  const std::vector<double> compute = {kCompute0Ms, 2 * kCompute0Ms, kCompute0Ms};
  const std::vector<double> host = {12.0, 2.0, 4.0};  // host scale 2
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(r.decisions[i].compute_ms, compute[i], 1e-12);
    EXPECT_NEAR(r.decisions[i].transfer_ms, kTransfer0Ms, 1e-9);  // from m = 100 points
    EXPECT_NEAR(r.decisions[i].host_ms, host[i], 1e-12);
    EXPECT_TRUE(r.decisions[i].offloaded);
  }
}

TEST(SystemModel, KernelThatDoesNotFitTheSpmSpillsToDram) {
  Platform p = test_platform("always");
  // Frame 0's gemm 3x100x4 needs (12 + 400 + 300) x 8 = 5696 B.
  p.backend = with_spm(*p.backend, 4096);
  p.power.dram_pj_per_byte = 2.0;
  const SystemResult r = simulate_system(p, three_frames(), kMeta, "t");
  const KernelDecision& d = r.decisions[0];
  EXPECT_FALSE(d.fits_spm);
  EXPECT_TRUE(d.offloaded);  // policy always: out of core
  // M = 512 doubles, t = ⌊√(512/3)⌋ = 13; W = 1200 MACs, ⌈2W/t⌉ = 185 < the 412 operands, so
  // read 412 x 8 = 3296 B, write 300 x 8 = 2400 B; each B + 200 ns on the 1 GB/s link.
  constexpr double kSpillMs = ((3296 + 200) + (2400 + 200)) * 1e-6;  // 0.006096 ms
  EXPECT_EQ(d.spill_bytes, 3296 + 2400);
  EXPECT_NEAR(d.spill_ms, kSpillMs, 1e-12);
  EXPECT_NEAR(d.accel_ms, kCompute0Ms + kTransfer0Ms + kSpillMs, 1e-12);
  // The DES (contention on) puts the spill on the link around the units: + up to one cycle.
  const double be0 = 20.0 - 12.0 + kCompute0Ms + kTransfer0Ms + kSpillMs;
  EXPECT_NEAR(r.accelerated.frames[0].backend_ms, be0 + 5e-6, 5e-6 + 1e-9);
  // Energy: the spill's 5696 B are DRAM bytes (2 pJ each) carried by the link (1 pJ each).
  Platform fits = p;
  fits.backend = with_spm(*fits.backend, 67108864);
  const SystemResult in_core = simulate_system(fits, three_frames(), kMeta, "t");
  const auto dynamic_j = [](const FrameResult& f) {
    return f.energy.compute_j + f.energy.memory_j + f.energy.link_j;
  };
  EXPECT_NEAR(dynamic_j(r.accelerated.frames[0]) - dynamic_j(in_core.accelerated.frames[0]),
              1e-12 * 5696 * (2.0 + 1.0), 1e-18);
  // The run summary counts both spilled invocations: frame 1's 3x100000x4 gemm also exceeds the
  // SPM (W 1.2e6, ⌈2W/13⌉ = 184616 < 400012 operands): 3 200 096 B read, 2 400 000 B written.
  EXPECT_EQ(r.decisions[1].spill_bytes, 3200096 + 2400000);
  const nlohmann::json offload = r.to_json()["offload"];
  EXPECT_EQ(offload["exceeding_spm"], 2);
  EXPECT_EQ(offload["spilled_offloaded"], 2);
  EXPECT_EQ(offload["spilled_bytes"], 5696 + 5600096);
  EXPECT_EQ(in_core.to_json()["offload"]["exceeding_spm"], 0);
  EXPECT_THAT(format_system_result(r),
              ::testing::HasSubstr("2 of 2 accelerable invocations exceed"));
}

TEST(SystemModel, EnergyByResourceAddsUpToTheStreamedRunsEnergy) {
  Platform p = test_platform("always");
  const SystemResult r = simulate_system(p, three_frames(), kMeta, "t");
  // Each accelerated frame's work energy, split by resource, adds up to its compute, memory
  // and link energy.
  for (const FrameResult& f : r.accelerated.frames) {
    EXPECT_NEAR(f.parts.total(), f.energy.compute_j + f.energy.memory_j + f.energy.link_j, 1e-15);
  }
  // Frame 0's projection on the multiply array: 800 busy cycles x 4 MACs x 10 pJ + its
  // operands' 5696 BRAM bytes x 1 pJ.
  EXPECT_NEAR(r.accelerated.frames[0].parts.backend[0], 1e-12 * (32000 + 5696), 1e-18);
  const StreamSummary& st = *r.accelerated.stream;
  std::map<std::string, cost::ResourceEnergy> by_name;
  double total = 0, work = 0;
  for (const cost::ResourceEnergy& e : st.energy_by_resource) {
    by_name[e.name] = e;
    total += e.energy_j;
  }
  for (const FrameResult& f : r.accelerated.frames) {
    work += f.energy.compute_j + f.energy.memory_j + f.energy.link_j;
  }
  EXPECT_NEAR(st.energy_j, total / 3.0, 1e-15);
  // With fpga_idle_fraction 0: static over the span, the host package, the frames' work.
  const double span = by_name.at("fpga.static").idle_s;  // the run's span T
  EXPECT_GT(span, 0.0);
  EXPECT_NEAR(by_name.at("fpga.static").energy_j, 1.0 * span, 1e-15);
  const cost::ResourceEnergy& host = by_name.at("host.cores");
  EXPECT_NEAR(host.busy_s + host.idle_s, span, 1e-15);
  EXPECT_NEAR(host.energy_j, 10.0 * host.busy_s + 1.0 * host.idle_s, 1e-15);
  EXPECT_NEAR(total, 1.0 * span + host.energy_j + work, 1e-12);
  // The multiply array: busy 800 + 800 000 cycles at 100 MHz (frames 0 and 1), idle the rest.
  const cost::ResourceEnergy& mul = by_name.at("backend.gemm");
  EXPECT_NEAR(mul.busy_s, 800'800 / 100e6, 1e-9);
  EXPECT_NEAR(mul.busy_s + mul.idle_s, span, 1e-15);
  EXPECT_EQ(mul.idle_w, 0.0);
  EXPECT_NEAR(mul.active_w * mul.busy_s, mul.energy_j, 1e-15);

  // An idle-but-clocked unit drawing half its busy power: the multiply array adds
  // 0.5 · active_w · idle_s, and so does every other unit; the host and static do not change.
  p.power.fpga_idle_fraction = 0.5;
  const SystemResult idle = simulate_system(p, three_frames(), kMeta, "t");
  double extra = 0;
  for (const cost::ResourceEnergy& e : idle.accelerated.stream->energy_by_resource) {
    const cost::ResourceEnergy& before = by_name.at(e.name);
    if (e.name.rfind("frontend.", 0) == 0 || e.name.rfind("backend.", 0) == 0) {
      EXPECT_NEAR(e.idle_w, 0.5 * e.active_w, 1e-12) << e.name;
      EXPECT_NEAR(e.energy_j, before.energy_j + 0.5 * before.active_w * before.idle_s, 1e-12)
          << e.name;
      extra += 0.5 * before.active_w * before.idle_s;
    } else {
      EXPECT_NEAR(e.energy_j, before.energy_j, 1e-15) << e.name;
    }
  }
  EXPECT_GT(extra, 0.0);
  EXPECT_NEAR(idle.accelerated.stream->energy_j, st.energy_j + extra / 3.0, 1e-12);
  // The baseline has the host alone.
  ASSERT_EQ(r.baseline.stream->energy_by_resource.size(), 1u);
  EXPECT_EQ(r.baseline.stream->energy_by_resource[0].name, "host.cores");
  EXPECT_TRUE(r.to_json()["accelerated"]["stream"]["energy_by_resource"].contains("dram"));
}

TEST(SystemModel, TheSchedulerSeesTheSpillCost) {
  // Frame 0's projection takes 0.016 ms on the host (8 µs x 2): in core the accelerator's
  // 0.013296 ms wins; with the spill's 0.006096 ms more the oracle keeps it on the host.
  std::vector<trace::FrameTrace> frames = three_frames();
  frames[0].kernels[0].host_ns = 8'000;
  Platform p = test_platform("oracle");
  EXPECT_TRUE(simulate_system(p, frames, kMeta, "t").decisions[0].offloaded);
  p.backend = with_spm(*p.backend, 4096);
  const SystemResult r = simulate_system(p, frames, kMeta, "t");
  EXPECT_FALSE(r.decisions[0].fits_spm);
  EXPECT_FALSE(r.decisions[0].offloaded);
  EXPECT_EQ(r.to_json()["offload"]["spilled_offloaded"], 0);
}

TEST(SystemModel, RegressionFitsOnTheFirstQuarterAndMatchesTheOracle) {
  // 8 frames; projection host time 50 µs + 0.1 µs per point (exactly linear), sizes alternate
  // between 10 and 100 000 points: the 2 training frames fit the line exactly.
  std::vector<trace::FrameTrace> frames;
  for (int i = 0; i < 8; ++i) {
    frames.push_back(frame(i, BackendMode::Registration, 50'000'000));
    const std::int64_t points = i % 2 == 0 ? 10 : 100'000;
    frames.back().kernels = {projection(points, 50'000 + points * 100)};
  }
  const SystemResult r = simulate_system(test_platform("regression"), frames, kMeta, "t");
  ASSERT_EQ(r.schedule.size(), 1u);
  EXPECT_EQ(r.schedule[0].invocations, 6u);  // 8 − ⌈0.25 x 8⌉ (one projection a frame)
  EXPECT_EQ(r.schedule[0].training_samples, 2u);
  EXPECT_TRUE(r.schedule[0].has_model);
  EXPECT_NEAR(r.schedule[0].r_squared_train, 1.0, 1e-9);
  EXPECT_NEAR(r.schedule[0].r_squared_eval, 1.0, 1e-9);
  EXPECT_NEAR(r.schedule[0].gap_to_oracle, 0.0, 1e-12);
  for (const KernelDecision& d : r.decisions) {
    EXPECT_EQ(d.training, d.frame_id < 2);
    // Host 2 x (50 µs + 0.1 µs x 10) = 0.102 ms against 0.0018 ms: offloaded; 100 000 points:
    // host 20.1 ms against 12.8 ms: offloaded too. Training frames stay on the host.
    EXPECT_EQ(d.offloaded, !d.training) << d.frame_id;
  }
}

TEST(SystemModel, EachKernelTrainsOnItsOwnInvocationsWhateverTheModeOrder) {
  // 4 SLAM frames without an accelerable kernel, then 8 registration frames with the projections
  // of the test above: the first 25 % of the frames (0..2) hold no projection, but the first
  // ⌈0.25 x 8⌉ = 2 projections (frames 4 and 5) fit the line exactly.
  std::vector<trace::FrameTrace> frames;
  for (int i = 0; i < 4; ++i) {
    frames.push_back(frame(i, BackendMode::Slam, 5'000'000));
    frames.back().kernels = {host_only(1'000'000)};
  }
  for (int i = 4; i < 12; ++i) {
    frames.push_back(frame(i, BackendMode::Registration, 50'000'000));
    const std::int64_t points = i % 2 == 0 ? 10 : 100'000;
    frames.back().kernels = {projection(points, 50'000 + points * 100)};
  }
  const SystemResult r = simulate_system(test_platform("regression"), frames, kMeta, "t");
  ASSERT_EQ(r.schedule.size(), 1u);
  EXPECT_EQ(r.schedule[0].training_samples, 2u);
  EXPECT_EQ(r.schedule[0].invocations, 6u);
  ASSERT_TRUE(r.schedule[0].has_model);
  EXPECT_NEAR(r.schedule[0].r_squared_eval, 1.0, 1e-9);
  for (const KernelDecision& d : r.decisions) {
    EXPECT_EQ(d.training, d.frame_id < 6) << d.frame_id;
    EXPECT_EQ(d.offloaded, !d.training) << d.frame_id;  // as in the test above
  }
}

TEST(ResultsDatabase, HoldsEveryTableAndReplacesARerun) {
  edx::testing::TempDir dir;
  const auto path = dir.path() / "results.db";
  const SystemResult r = simulate_system(test_platform("oracle"), three_frames(), kMeta, "t.db");
  write_results(path, result_rows(r));
  write_results(path, result_rows(r));  // same config and trace: replaced, not duplicated
  Platform other = test_platform("never");
  write_results(path, result_rows(simulate_system(other, three_frames(), kMeta, "t.db")));

  SQLite::Database db(path.string());
  EXPECT_EQ(db.execAndGet("SELECT COUNT(*) FROM runs").getInt(), 2);
  const std::string run = r.config_hash + "-" + r.trace_hash;
  const auto count = [&](const std::string& sql) {
    SQLite::Statement s(db, sql);
    s.bind(1, run);
    s.executeStep();
    return s.getColumn(0).getDouble();
  };
  EXPECT_EQ(count("SELECT COUNT(*) FROM frames WHERE run_id = ?"), 6);  // 3 frames x 2 variants
  EXPECT_NEAR(count("SELECT e2e_ms FROM frames WHERE run_id = ? AND variant = 'baseline' AND "
                    "frame_id = 1"),
              43.0, 1e-9);
  EXPECT_EQ(count("SELECT offloaded FROM offload WHERE run_id = ? AND frame_id = 0"), 1);
  EXPECT_EQ(count("SELECT COUNT(*) FROM offload WHERE run_id = ?"), 2);
  // Spill time and bytes are stored for every invocation (0 when it fits the SPM).
  EXPECT_EQ(count("SELECT COUNT(spill_ms) + COUNT(spill_bytes) FROM offload WHERE run_id = ?"), 4);
  // 3 modes (registration, slam, all) x 3 stages x 2 variants.
  EXPECT_EQ(count("SELECT COUNT(*) FROM latency WHERE run_id = ?"), 18);
  EXPECT_NEAR(count("SELECT mean FROM latency WHERE run_id = ? AND variant = 'baseline' AND "
                    "mode = 'registration' AND stage = 'e2e'"),
              33.0, 1e-9);
  EXPECT_NEAR(count("SELECT fps_with_pipelining FROM throughput WHERE run_id = ? AND "
                    "variant = 'baseline'"),
              40.0, 1e-9);
  EXPECT_NEAR(count("SELECT mean_j FROM energy WHERE run_id = ? AND variant = 'baseline' AND "
                    "mode = 'slam'"),
              0.13, 1e-12);
  EXPECT_GT(count("SELECT dsp FROM resources WHERE run_id = ? AND entry = 'total'"), 0);
  EXPECT_EQ(count("SELECT COUNT(*) FROM schedule WHERE run_id = ?"), 1);
}

TEST(ResultsDatabase, FailedWriteLeavesNothing) {
  edx::testing::TempDir dir;
  const auto path = dir.path() / "bad.db";
  {  // An older file whose frames table has other columns: the insert fails.
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    db.exec("CREATE TABLE frames (run_id TEXT, x INTEGER)");
  }
  const SystemResult r = simulate_system(test_platform("oracle"), three_frames(), kMeta, "t.db");
  EXPECT_THROW(write_results(path, result_rows(r)), std::runtime_error);
  SQLite::Database db(path.string());
  EXPECT_FALSE(db.tableExists("runs"));  // the whole transaction was rolled back
}

}  // namespace
}  // namespace edx::arch
