// The op-count host model (arch/host/host_costs.hpp): the fit recovers costs that generated the
// times, keeps every cost >= 0, modeled host times read the work and never the measured times,
// and the cost table's errors name the file, line and key.
#include "arch/host/host_costs.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "arch/host/host_processor.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;
using trace::FrameTrace;

// The tracing machine of the synthetic traces: its suite parts take 50 ms and 5 ms.
const trace::TraceMeta kMeta = {
    {"host_speed", R"({"suite": 1, "frontend_ms": 50.0, "backend_ms": 5.0, "samples": 3})"}};

// The costs the synthetic times are made from (ns per unit per suite-ms).
constexpr double kIfCall = 300, kIfPixel = 0.02;                    // IF: call, pixels
constexpr double kSolveCall = 40, kSolveM2 = 0.5, kSolveM3 = 0.01;  // solve: call, m², m³
constexpr double kFrontendRest = 7, kBackendRest = 3;

/// Frames of an IF task and a `solve` kernel whose host times are exactly the costs above times
/// the tracing machine's suite times, for random work.
std::vector<FrameTrace> synthetic_frames(std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pixels(1000, 400000), m(5, 300);
  std::vector<FrameTrace> frames;
  for (std::size_t f = 0; f < count; ++f) {
    FrameTrace frame;
    frame.frame.frame_id = static_cast<std::int64_t>(f);
    frame.frame.mode = trace::BackendMode::Slam;
    trace::TaskRecord task;
    task.task = trace::Task::IF;
    task.pixels = pixels(rng);
    task.host_ns = std::llround(50.0 * (kIfCall + kIfPixel * double(task.pixels)));
    trace::KernelRecord kernel;
    kernel.kernel = "solve";
    kernel.m = m(rng);
    const double md = double(kernel.m);
    kernel.host_ns =
        std::llround(5.0 * (kSolveCall + kSolveM2 * md * md + kSolveM3 * md * md * md));
    frame.frame.frontend_host_ns = task.host_ns + std::llround(50.0 * kFrontendRest);
    frame.frame.backend_host_ns = kernel.host_ns + std::llround(5.0 * kBackendRest);
    frame.tasks.push_back(task);
    frame.kernels.push_back(kernel);
    frames.push_back(frame);
  }
  return frames;
}

TEST(HostCosts, TheFitRecoversTheCostsTheTimesWereMadeOf) {
  const std::vector<FrameTrace> frames = synthetic_frames(60, 1);
  const HostCostModel model = fit_host_costs({{"s.db", &frames, &kMeta}}, "test");
  EXPECT_EQ(model.suite, 1);
  const RowCost& if_cost = model.frontend.at("IF");
  ASSERT_EQ(if_cost.features, (std::vector<std::string>{"call", "pixels"}));
  EXPECT_NEAR(if_cost.costs[0], kIfCall, 1e-3 * kIfCall);
  EXPECT_NEAR(if_cost.costs[1], kIfPixel, 1e-6 * kIfPixel);
  const RowCost& solve = model.backend.at("solve");
  ASSERT_EQ(solve.features, (std::vector<std::string>{"call", "m2", "m3"}));
  EXPECT_NEAR(solve.costs[0], kSolveCall, 1e-2 * kSolveCall);
  EXPECT_NEAR(solve.costs[1], kSolveM2, 1e-4 * kSolveM2);
  EXPECT_NEAR(solve.costs[2], kSolveM3, 1e-6 * kSolveM3);
  EXPECT_GT(solve.r2, 0.999999);
  EXPECT_NEAR(model.frontend.at("frontend_rest").costs[0], kFrontendRest, 0.01);
  EXPECT_NEAR(model.backend.at("backend_rest:slam").costs[0], kBackendRest, 0.2);
  // The shares are of the measured time per part: IF and the frontend rest make the frontend.
  EXPECT_NEAR(if_cost.measured_share + model.frontend.at("frontend_rest").measured_share, 1.0,
              1e-12);
}

TEST(HostCosts, AFitWithoutFramesIsRefusedAndThinKindsAreNamed) {
  const std::vector<FrameTrace> none;
  EXPECT_THAT(
      [&] {
        fit_host_costs({{"empty.db", &none, &kMeta}}, "test");
      },
      ::testing::ThrowsMessage<std::runtime_error>(
          ::testing::StrEq("empty.db: the trace has no frames to fit")));
  // Two frames: IF (call, pixels) needs 6 rows, solve (call, m2, m3) 9, the rests 3 and 6.
  const std::vector<FrameTrace> two = synthetic_frames(2, 1);
  const std::vector<std::string> warnings =
      fit_warnings(fit_host_costs({{"two.db", &two, &kMeta}}, "test"));
  EXPECT_THAT(warnings, ::testing::Contains(
                            "kind 'IF' fitted from 2 rows: its per-call cost alone (all 2 costs "
                            "need 6 rows)"));
  EXPECT_THAT(warnings,
              ::testing::Contains("kind 'solve' fitted from 2 rows: its per-call cost alone (all 3 "
                                  "costs need 9 rows)"));
  // 60 frames fit every cost of every kind: no warning.
  const std::vector<FrameTrace> sixty = synthetic_frames(60, 1);
  EXPECT_TRUE(fit_warnings(fit_host_costs({{"s.db", &sixty, &kMeta}}, "test")).empty());
}

// The VIO's `jacobians` kernel: its sizes and the whitening's flops from its detail (0 without).
TEST(HostCosts, JacobiansWorkIncludesTheWhiteningFlopsOfItsDetail) {
  trace::KernelRecord kernel;
  kernel.kernel = "jacobians";
  kernel.m = 40;
  kernel.n = 81;
  kernel.k = 7;
  kernel.detail_json = R"({"whitening_flops": 12345.5})";
  const WorkRow row = work_of(kernel);
  EXPECT_EQ(feature_names(CostPart::kBackendKernel, "jacobians"),
            (std::vector<std::string>{"call", "mn", "k", "whitening_flops"}));
  EXPECT_EQ(row.x, (std::vector<double>{1.0, 40.0 * 81.0, 7.0, 12345.5}));
  kernel.detail_json = "{}";
  EXPECT_EQ(work_of(kernel).x.back(), 0.0);
}

TEST(HostCosts, ACostThatComesOutNegativeIsDroppedAndTheKindRefitted) {
  // solve times falling with m² (no real kernel does): least squares would give m² a negative
  // cost; it is dropped, and so is m³, leaving the mean per call.
  std::vector<FrameTrace> frames = synthetic_frames(30, 2);
  double sum = 0;
  for (FrameTrace& f : frames) {
    const double m = double(f.kernels[0].m);
    f.kernels[0].host_ns = std::llround(5.0 * (200000 - 2.0 * m * m));
    f.frame.backend_host_ns = f.kernels[0].host_ns;
    sum += double(f.kernels[0].host_ns) / 5.0;
  }
  const HostCostModel model = fit_host_costs({{"s.db", &frames, &kMeta}}, "test");
  const RowCost& solve = model.backend.at("solve");
  for (double c : solve.costs) EXPECT_GE(c, 0.0);
  EXPECT_EQ(solve.costs[1], 0.0);
  EXPECT_EQ(solve.costs[2], 0.0);
  EXPECT_NEAR(solve.costs[0], sum / double(frames.size()), 1e-6 * sum);
}

TEST(HostCosts, ModeledTimesAreTheCostsTimesTheWorkTimesTheHostsSuiteTime) {
  const std::vector<FrameTrace> frames = synthetic_frames(40, 3);
  const HostCostModel model = fit_host_costs({{"s.db", &frames, &kMeta}}, "test");
  // Suite times twice the tracing machine's 50 ms and four times its 5 ms.
  const auto host =
      make_host_processor("suite_scaled", "{frontend_suite_ms: 100, backend_suite_ms: 20}");
  const PlatformHostTimes t = host->host_times(frames, kMeta, "s.db", &model);
  EXPECT_EQ(t.source, HostTimeSource::kModeled);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    // The times were made exactly of the costs, so modeled = measured × the suite-time ratio.
    EXPECT_NEAR(t.frontend_ms[f], 2.0 * 1e-6 * double(frames[f].frame.frontend_host_ns),
                1e-4 * t.frontend_ms[f]);
    EXPECT_NEAR(t.kernel_ms[f][0], 4.0 * 1e-6 * double(frames[f].kernels[0].host_ns),
                1e-3 * t.kernel_ms[f][0]);
    EXPECT_NEAR(t.backend_ms[f], 4.0 * 1e-6 * double(frames[f].frame.backend_host_ns),
                1e-3 * t.backend_ms[f]);
  }
}

TEST(HostCosts, ModeledTimesNeverReadTheMeasuredOnes) {
  // The committed reference trace, and the same work with every host time and the machine's
  // speed scrambled (another machine under another load): identical modeled host times on both
  // platforms; measured times move.
  const std::filesystem::path golden =
      std::filesystem::path(EDX_SOURCE_DIR) / "tests" / "data" / "golden" / "golden_mix.db";
  const trace::TraceReader reader(golden);
  const std::vector<FrameTrace> frames = reader.read_all();
  std::vector<FrameTrace> scrambled = frames;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> factor(0.5, 2.0);
  const auto scale = [&](std::int64_t& ns) { ns = std::llround(double(ns) * factor(rng)); };
  for (FrameTrace& f : scrambled) {
    scale(f.frame.frontend_host_ns);
    scale(f.frame.backend_host_ns);
    for (trace::TaskRecord& t : f.tasks) scale(t.host_ns);
    for (trace::KernelRecord& k : f.kernels) scale(k.host_ns);
  }
  trace::TraceMeta other = reader.meta();
  other["host_speed"] = R"({"suite": 1, "frontend_ms": 400.0, "backend_ms": 70.0, "samples": 3})";
  const std::string suite_times = "frontend_suite_ms: 170.03, backend_suite_ms: 48.01";
  const auto host = make_host_processor("suite_scaled", "{" + suite_times + "}");
  const PlatformHostTimes a = host->host_times(frames, reader.meta(), "a");
  const PlatformHostTimes b = host->host_times(scrambled, other, "b");
  EXPECT_EQ(a.frontend_ms, b.frontend_ms);
  EXPECT_EQ(a.backend_ms, b.backend_ms);
  EXPECT_EQ(a.kernel_ms, b.kernel_ms);
  double total = 0;
  for (double ms : a.frontend_ms) total += ms;
  EXPECT_GT(total, 0.0);
  const auto measured =
      make_host_processor("suite_scaled", "{times: measured, " + suite_times + "}");
  const PlatformHostTimes ma = measured->host_times(frames, reader.meta(), "a");
  const PlatformHostTimes mb = measured->host_times(scrambled, other, "b");
  EXPECT_EQ(ma.source, HostTimeSource::kMeasured);
  EXPECT_NE(ma.frontend_ms, mb.frontend_ms);
}

TEST(HostCosts, TheBundledTableCostsEveryKindThePipelineRecords) {
  const HostCostModel& bundled = HostCostModel::bundled();
  EXPECT_EQ(bundled.suite, trace::kHostSpeedSuite);
  for (const char* task : {"FD", "IF", "FC", "MO", "DR", "DC", "LSS", "frontend_rest"}) {
    EXPECT_TRUE(bundled.frontend.contains(task)) << task;
  }
  for (const char* kernel :
       {"projection", "kalman_gain", "marginalization", "nullspace_projection", "covariance_update",
        "linearization", "schur_complement", "solve", "lm_iteration", "pnp", "bow_query",
        "backend_rest:vio", "backend_rest:slam", "backend_rest:registration"}) {
    EXPECT_TRUE(bundled.backend.contains(kernel)) << kernel;
  }
}

TEST(HostCosts, ATableRoundTripsThroughYaml) {
  const std::vector<FrameTrace> frames = synthetic_frames(30, 4);
  const HostCostModel model = fit_host_costs({{"s.db", &frames, &kMeta}}, "round trip");
  const HostCostModel back = HostCostModel::from_yaml(YAML::Load(model.to_yaml()), "t.yaml");
  EXPECT_EQ(back.suite, model.suite);
  EXPECT_EQ(back.provenance, "round trip");
  for (const auto& [kind, cost] : model.backend) {
    ASSERT_TRUE(back.backend.contains(kind));
    for (std::size_t j = 0; j < cost.costs.size(); ++j) {
      EXPECT_NEAR(back.backend.at(kind).costs[j], cost.costs[j], 1e-9 * cost.costs[j]);
    }
  }
}

// A partial re-fit (edx host-costs fit --only): the named kinds take the new fit's costs, the
// others keep the base table's; a kind the traces lack and a base of another suite are errors.
TEST(HostCosts, APartialRefitReplacesOnlyTheNamedKinds) {
  const std::vector<FrameTrace> frames = synthetic_frames(30, 5);
  HostCostModel base = fit_host_costs({{"s.db", &frames, &kMeta}}, "base");
  base.frontend.at("IF").costs = {1.0, 2.0};
  base.backend.at("solve").costs = {3.0, 4.0, 5.0};
  const HostCostModel fitted = fit_host_costs({{"s.db", &frames, &kMeta}}, "new");
  const HostCostModel merged = replace_kinds(base, fitted, {"solve"});
  EXPECT_EQ(merged.backend.at("solve").costs, fitted.backend.at("solve").costs);
  EXPECT_EQ(merged.frontend.at("IF").costs, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(merged.provenance, "base; solve re-fitted: new");
  EXPECT_THAT([&] { replace_kinds(base, fitted, {"normal_equations"}); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("kind 'normal_equations': the traces have no rows of it")));
  base.suite = 2;
  EXPECT_THAT([&] { replace_kinds(base, fitted, {"solve"}); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  HasSubstr("the base table is of suite v2, the traces of v1")));
}

TEST(HostCosts, ErrorsNameTheFileLineAndKey) {
  const auto error_of = [](const std::string& text) {
    try {
      HostCostModel::from_yaml(YAML::Load(text), "costs.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of("suite: 1\nfrontend:\n  IF: {features: [call, area], costs: [1, 2], "
                       "samples: 3, r2: 1, share: 1}\nbackend: {}\n"),
              HasSubstr("costs.yaml:3: frontend.IF: features [call, area], but this edx models "
                        "[call, pixels]"));
  EXPECT_THAT(error_of("suite: 1\nfrontend:\n  IF: {features: [call, pixels], costs: [1, -2], "
                       "samples: 3, r2: 1, share: 1}\nbackend: {}\n"),
              HasSubstr("costs.yaml:3: frontend.IF.costs: expected a list of numbers >= 0, got "
                        "'-2'"));
  EXPECT_THAT(error_of("suite: one\nfrontend: {}\nbackend: {}\n"),
              HasSubstr("costs.yaml:1: suite: expected the reference-suite version"));
  EXPECT_THAT(error_of("suite: 1\nfrontend:\n  XX: {features: [call], costs: [1], samples: 1, "
                       "r2: 1, share: 1}\nbackend: {}\n"),
              HasSubstr("frontend.XX: not a frontend task"));
  EXPECT_THAT(error_of("suite: 1\nfrontend: {}\nbackend: {}\nextra: 1\n"), HasSubstr("extra"));

  // A row the table has no costs for: the trace, frame and kind.
  const std::vector<FrameTrace> frames = synthetic_frames(30, 5);
  HostCostModel model = fit_host_costs({{"s.db", &frames, &kMeta}}, "test");
  model.backend.erase("solve");
  const auto host =
      make_host_processor("suite_scaled", "{frontend_suite_ms: 1, backend_suite_ms: 1}");
  try {
    host->host_times(frames, kMeta, "s.db", &model);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("s.db: frame 0: the host cost table (suite v1) has no costs "
                                    "for 'solve'"));
  }
  // A trace without host speed cannot be fitted on.
  const trace::TraceMeta bare;
  EXPECT_THROW(fit_host_costs({{"bare.db", &frames, &bare}}, "x"), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
