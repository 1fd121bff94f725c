// Processors from their datasheets (arch/host/throughput.hpp, processors/datasheet.cpp; issue
// 41): each class's rate by hand from the datasheet figures, every kind of the bundled cost
// table with a declared bound, an anchor equal to the suite_scaled host of the same suite
// times, a predicted processor's rows scaled by their bounds' rate ratios (hand-computed), the
// bundled descriptions and their errors, and a platform whose baseline runs on another host.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "arch/host/host_costs.hpp"
#include "arch/host/host_processor.hpp"
#include "arch/host/throughput.hpp"
#include "arch/platform/platform.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/host/platform_text.hpp"
#include "tests/arch/system/hand_tasks.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;
using C = ThroughputClass;

TEST(Throughput, EachClassRateFollowsTheDatasheet) {
  const ProcessorDatasheet kaby_lake;  // the defaults: the paper's Kaby Lake
  EXPECT_DOUBLE_EQ(kaby_lake.rate(C::kScalar), 1.6 * 4);
  // 128-bit code on three 256-bit vector ALUs: 8 lanes of 16 bits each, a pipe.
  EXPECT_DOUBLE_EQ(kaby_lake.rate(C::kSimdInteger), 1.6 * 3 * 8);
  // 16 double flops a cycle at 256 bits; the code's 128 bits use half.
  EXPECT_DOUBLE_EQ(kaby_lake.rate(C::kFloat64), 1.6 * 16 / 2);
  EXPECT_DOUBLE_EQ(kaby_lake.rate(C::kFloat32), 1.6 * 32 / 2);
  EXPECT_DOUBLE_EQ(kaby_lake.rate(C::kMemory), 38.4);

  ProcessorDatasheet in_order;
  in_order.clock_ghz = 1.2;
  in_order.issue_width = 2;
  in_order.out_of_order = false;
  in_order.simd_bits = 64;
  in_order.simd_int_pipes = 1;
  in_order.fp64_flops_per_cycle = 2;
  // (2.3 / 4.1) / (2 / 3) = 0.8415: ARM's Dhrystone per clock of the A53 over the A57's, per
  // issue slot.
  EXPECT_NEAR(in_order.rate(C::kScalar), 1.2 * 2 * 0.841463, 1e-5);
  EXPECT_DOUBLE_EQ(in_order.rate(C::kSimdInteger), 1.2 * 1 * 4);  // 64 bits: 4 lanes
  EXPECT_DOUBLE_EQ(in_order.rate(C::kFloat64), 1.2 * 2);          // narrower than the code
}

TEST(Throughput, EveryKindOfTheBundledCostTableHasADeclaredBound) {
  const HostCostModel& table = HostCostModel::bundled();
  for (const auto& [kind, cost] : table.frontend) {
    const CostPart part =
        kind == "frontend_rest" ? CostPart::kFrontendRest : CostPart::kFrontendTask;
    EXPECT_TRUE(has_declared_bound(part, kind)) << kind;
  }
  for (const auto& [kind, cost] : table.backend) {
    const CostPart part =
        kind.starts_with("backend_rest:") ? CostPart::kBackendRest : CostPart::kBackendKernel;
    EXPECT_TRUE(has_declared_bound(part, kind)) << kind;
  }
  EXPECT_EQ(bound_of(CostPart::kFrontendTask, "FD"), C::kSimdInteger);
  EXPECT_EQ(bound_of(CostPart::kFrontendTask, "FC"), C::kScalar);
  EXPECT_EQ(bound_of(CostPart::kBackendKernel, "kalman_gain"), C::kFloat64);
  EXPECT_EQ(bound_of(CostPart::kBackendKernel, "cloning"), C::kMemory);
  EXPECT_EQ(bound_of(CostPart::kBackendKernel, "tracking"), C::kScalar);
  EXPECT_FALSE(has_declared_bound(CostPart::kBackendKernel, "a_newer_kernel"));
  EXPECT_EQ(bound_of(CostPart::kBackendKernel, "a_newer_kernel"), C::kScalar);
}

TEST(Throughput, TheModelDocListsEveryBound) {
  std::ifstream in(std::string(EDX_SOURCE_DIR) + "/docs/MODEL.md");
  const std::string model((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(model, HasSubstr(bounds_markdown()))
      << "docs/MODEL.md's bound table is stale: paste `edx host-costs bounds` into it";
}

TEST(DatasheetHost, AnAnchorHasTheTimesOfItsSuiteTimes) {
  const Platform anchor = parse("name: p\nhost: {kind: datasheet, processor: kaby_lake_4c}\n");
  EXPECT_EQ(anchor.host->kind(), "datasheet");
  EXPECT_EQ(anchor.host->cores(), 4);
  EXPECT_EQ(anchor.host->power().active_w, 15.0);
  EXPECT_EQ(anchor.host->params_json()["processor"], "kaby_lake_4c");
  const std::vector<trace::FrameTrace> frames = {hand_frame()};
  const double fe_suite = anchor.host->params_json()["frontend_suite_ms"];
  const double be_suite = anchor.host->params_json()["backend_suite_ms"];
  for (const char* times : {"modeled", "measured"}) {
    const std::string set = std::string("\n  times: ") + times + "\n";
    const Platform a = parse("name: p\nhost:\n  kind: datasheet\n  processor: kaby_lake_4c" + set);
    const Platform s =
        parse(fmt::format("name: p\nhost:\n  frontend_suite_ms: {}\n  backend_suite_ms: {}{}",
                          fe_suite, be_suite, set));
    const PlatformHostTimes ta = a.host->host_times(frames, hand_meta(), "hand.db");
    const PlatformHostTimes ts = s.host->host_times(frames, hand_meta(), "hand.db");
    EXPECT_EQ(ta.frontend_ms, ts.frontend_ms) << times;
    EXPECT_EQ(ta.backend_ms, ts.backend_ms) << times;
    EXPECT_EQ(ta.kernel_ms, ts.kernel_ms) << times;
    EXPECT_EQ(ta.task_ms, ts.task_ms) << times;
  }
}

/// A frame with measured task and kernel times: FD 1 ms (SIMD integer) and FC 0.5 ms (scalar)
/// of a 3 ms frontend; tracking 4 ms (scalar) and cloning 2 ms (memory) of a 10 ms backend.
trace::FrameTrace measured_frame() {
  trace::FrameTrace f = hand_frame("tracking", 4'000'000);
  for (trace::TaskRecord& t : f.tasks) {
    if (t.task == trace::Task::FD && t.image == trace::Image::Left) t.host_ns = 1'000'000;
    if (t.task == trace::Task::FC && t.image == trace::Image::Left) t.host_ns = 500'000;
  }
  trace::KernelRecord cloning;
  cloning.kernel = "cloning";
  cloning.host_ns = 2'000'000;
  f.kernels.push_back(cloning);
  return f;
}

TEST(DatasheetHost, APredictedProcessorScalesEachRowByItsBoundsRateRatio) {
  // The Kaby Lake's datasheet at half its clock, efficiency 1.25: compute rows take
  // 2 / 1.25 = 1.6 x the anchor's time; memory rows (the same DRAM bandwidth) 1 / 1.25 = 0.8 x.
  const std::string predicted =
      "name: p\nhost:\n  kind: datasheet\n  reference: kaby_lake_4c\n  times: measured\n"
      "  clock_ghz: 0.8\n  efficiency: 1.25\n";
  const Platform half = parse(predicted + "  memory_gb_per_s: 38.4\n");
  const std::vector<trace::FrameTrace> frames = {measured_frame()};
  const PlatformHostTimes t = half.host->host_times(frames, hand_meta(), "hand.db");
  // The anchor maps measured times by its suite times over the trace's, 10 ms and 4 ms.
  const nlohmann::json kaby_lake =
      parse("name: p\nhost: {kind: datasheet, processor: kaby_lake_4c}\n").host->params_json();
  const double fe = kaby_lake["frontend_suite_ms"].get<double>() / 10;
  const double be = kaby_lake["backend_suite_ms"].get<double>() / 4;
  EXPECT_NEAR(t.frontend_ms[0], 1.6 * 3 * fe, 1e-9);  // every frontend row is compute
  EXPECT_NEAR(t.task_ms[0][0], 1.6 * 1 * fe, 1e-9);   // FD
  // tracking (scalar), cloning (memory, the same bandwidth: 1 / 1.25), the rest (scalar).
  EXPECT_NEAR(t.kernel_ms[0][0], 1.6 * 4 * be, 1e-9);
  EXPECT_NEAR(t.kernel_ms[0][1], 0.8 * 2 * be, 1e-9);
  EXPECT_NEAR(t.backend_ms[0], (1.6 * 4 + 0.8 * 2 + 1.6 * 4) * be, 1e-9);
  EXPECT_THAT(t.mapping.backend_basis(), HasSubstr("efficiency 1.25"));

  // Modeled times scale the same way: each row's modeled time x its ratio.
  const Platform modeled =
      parse("name: p\nhost:\n  kind: datasheet\n  reference: kaby_lake_4c\n  clock_ghz: 0.8\n");
  const Platform anchor = parse("name: p\nhost: {kind: datasheet, processor: kaby_lake_4c}\n");
  const PlatformHostTimes tm = modeled.host->host_times(frames, hand_meta(), "hand.db");
  const PlatformHostTimes ta = anchor.host->host_times(frames, hand_meta(), "hand.db");
  for (std::size_t i = 0; i < ta.task_ms[0].size(); ++i) {
    EXPECT_NEAR(tm.task_ms[0][i], 2 * ta.task_ms[0][i], 1e-12) << i;
  }
  EXPECT_NEAR(tm.kernel_ms[0][0], 2 * ta.kernel_ms[0][0], 1e-12);  // tracking: scalar
  EXPECT_NEAR(tm.kernel_ms[0][1], ta.kernel_ms[0][1], 1e-12);      // cloning: memory
}

TEST(DatasheetHost, TheBundledProcessorsLoadAndShareTheA57sEfficiency) {
  const Platform a57 = parse("name: p\nhost: {kind: datasheet, processor: cortex_a57_tx1}\n");
  const Platform a53 = parse("name: p\nhost: {kind: datasheet, processor: cortex_a53_zu9cg}\n");
  EXPECT_EQ(a53.host->params_json()["efficiency"], a57.host->params_json()["efficiency"]);
  EXPECT_THAT(a53.host->params_json()["efficiency_provenance"].get<std::string>(),
              HasSubstr("cortex_a57_tx1's: calibrated"));
  EXPECT_EQ(a53.host->params_json()["reference"], "kaby_lake_4c");
  // An efficiency given beside the description replaces the shared one.
  const Platform own =
      parse("name: p\nhost: {kind: datasheet, processor: cortex_a53_zu9cg, efficiency: 0.5}\n");
  EXPECT_EQ(own.host->params_json()["efficiency"], 0.5);
  EXPECT_EQ(own.host->params_json()["efficiency_of"], "");
  EXPECT_EQ(own.host->params_json()["efficiency_provenance"], "set in the platform file");
}

TEST(DatasheetHost, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("name: p\nhost:\n  kind: datasheet\n  processor: pentium\n"),
            "p.yaml:4: host.processor: expected a bundled processor (cortex_a53_zu9cg, "
            "cortex_a57_tx1, kaby_lake_4c, kryo_sd820), got 'pentium'");
  EXPECT_EQ(error_of("name: p\nhost:\n  kind: datasheet\n  reference: cortex_a53_zu9cg\n"),
            "p.yaml:4: host.reference: expected an anchor processor (one with suite times), "
            "got 'cortex_a53_zu9cg', itself predicted");
  EXPECT_THAT(error_of("name: p\nhost:\n  kind: datasheet\n  cores: 2\n"),
              HasSubstr("host.frontend_suite_ms: expected both suite times of an anchor"));
  EXPECT_THAT(error_of("name: p\nhost:\n  kind: datasheet\n  processor: cortex_a57_tx1\n"
                       "  backend_suite_ms: 3\n"),
              HasSubstr("host.frontend_suite_ms: expected no suite times on a processor "
                        "predicted from a `reference`"));
  EXPECT_EQ(error_of("name: p\nhost:\n  kind: datasheet\n  processor: cortex_a57_tx1\n"
                     "  efficiency_of: cortex_a53_zu9cg\n"),
            "p.yaml:5: host.efficiency_of: expected a processor that states its own efficiency, "
            "got 'cortex_a53_zu9cg', which shares another's");
  EXPECT_EQ(error_of("name: p\nhost:\n  kind: datasheet\n  processor: kaby_lake_4c\n"
                     "  simd_bits: 32\n"),
            "p.yaml:5: host.simd_bits: expected an integer in [64, 2048], got '32'");
}

TEST(BaselineHost, TheBaselineRunsOnItsOwnHostAndTheAcceleratedSystemOnTheOther) {
  const Platform p = parse(
      "name: p\nhost: {kind: fixed_speed, speed: 2, cores: 1, active_w: 20, idle_w: 1}\n"
      "baseline_host: {kind: fixed_speed, speed: 1, cores: 1, active_w: 10, idle_w: 1}\n");
  EXPECT_EQ(p.host_of(true).power().active_w, 20.0);
  EXPECT_EQ(p.host_of(false).power().active_w, 10.0);
  EXPECT_EQ(p.to_json()["baseline_host"]["speed"], 1.0);
  EXPECT_FALSE(parse("name: p\n").to_json().contains("baseline_host"));

  const std::vector<trace::FrameTrace> frames = {hand_frame("tracking", 4'000'000)};
  const SystemResult r = simulate_system(p, frames, hand_meta(), "hand.db");
  // The baseline on the speed-1 host: the trace's 3 ms and 10 ms; its energy at its 10 W.
  const FrameResult& b = r.baseline.frames[0];
  EXPECT_NEAR(b.frontend_ms, 3.0, 1e-9);
  EXPECT_NEAR(b.backend_ms, 10.0, 1e-9);
  EXPECT_NEAR(b.energy.host_j, 10.0 * 13e-3, 1e-12);
  // The accelerated system's backend (tracking stays on the host) on the speed-2 host.
  EXPECT_NEAR(r.accelerated.frames[0].backend_ms, 5.0, 1e-9);
}

}  // namespace
}  // namespace edx::arch
