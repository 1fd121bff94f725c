// Offload coprocessors of a CPU baseline (arch/host/coprocessor.hpp, coprocessors/; issue 41):
// each kind's rates by hand from its datasheet figures, a row's device time as the anchor's times
// its bound's rate ratio (and the sparse efficiency on the backend), the bundled devices and their
// shared efficiency, the rows a kind refuses, and the baseline of a platform with a device, its
// frontend stages and backend by hand.
#include "arch/host/coprocessor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "arch/host/frontend_graph.hpp"
#include "arch/platform/platform.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/host/platform_text.hpp"
#include "tests/arch/system/hand_tasks.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;
using C = ThroughputClass;

const OffloadDevice& device_of(const std::shared_ptr<const Coprocessor>& c) {
  return dynamic_cast<const OffloadDevice&>(*c);
}

TEST(Coprocessor, EachKindsRatesFollowItsDatasheet) {
  const auto gpu =
      make_coprocessor("gpu",
                       "{clock_ghz: 0.5, int16_ops_per_cycle: 100, fp32_flops_per_cycle: 400, "
                       "fp64_flops_per_cycle: 0, memory_gb_per_s: 20}");
  EXPECT_DOUBLE_EQ(device_of(gpu).rate(C::kSimdInteger), 50);
  EXPECT_DOUBLE_EQ(device_of(gpu).rate(C::kFloat32), 200);
  EXPECT_DOUBLE_EQ(device_of(gpu).rate(C::kFloat64), 200);  // no fp64: the fp32 rate
  EXPECT_DOUBLE_EQ(device_of(gpu).rate(C::kMemory), 20);
  const auto fp64 = make_coprocessor("gpu", "{clock_ghz: 0.5, fp64_flops_per_cycle: 16}");
  EXPECT_DOUBLE_EQ(device_of(fp64).rate(C::kFloat64), 8);
  // Two 1024-bit units, 64 lanes of 16 bits, two vector operations a cycle, at 0.5 GHz.
  const auto dsp = make_coprocessor(
      "dsp", "{clock_ghz: 0.5, vector_units: 2, vector_bits: 1024, vector_ops_per_cycle: 2}");
  EXPECT_DOUBLE_EQ(device_of(dsp).rate(C::kSimdInteger), 128);
  EXPECT_THROW((void)device_of(dsp).rate(C::kFloat64), std::logic_error);
}

TEST(Coprocessor, ARowsDeviceTimeIsTheAnchorsTimesItsRateRatio) {
  // A GPU of 76.8 16-bit lane operations a ns (2x one Kaby Lake core's 38.4) and 3.2 double
  // flops a ns (a quarter of its 12.8), e 0.5 on the backend: FD takes half the anchor's time,
  // kalman_gain 4 / 0.5 = 8 times it; FC (not stated) keeps the anchor's.
  const auto gpu =
      make_coprocessor("gpu",
                       "{clock_ghz: 1, int16_ops_per_cycle: 76.8, fp64_flops_per_cycle: 3.2, "
                       "sparse_efficiency: 0.5, tasks: [FD], kernels: [kalman_gain]}");
  EXPECT_TRUE(gpu->runs(CostPart::kFrontendTask, "FD"));
  EXPECT_FALSE(gpu->runs(CostPart::kFrontendTask, "FC"));
  EXPECT_TRUE(gpu->runs(CostPart::kBackendKernel, "kalman_gain"));
  const std::vector<trace::FrameTrace> frames = {hand_frame("kalman_gain", 4'000'000)};
  const PlatformHostTimes dev = gpu->device_times(frames, hand_meta(), "hand.db");
  const PlatformHostTimes ref = make_host_processor("datasheet", "{processor: kaby_lake_4c}")
                                    ->host_times(frames, hand_meta(), "hand.db");
  for (std::size_t i = 0; i < frames[0].tasks.size(); ++i) {
    const bool fd = frames[0].tasks[i].task == trace::Task::FD;
    if (fd) {
      ASSERT_GT(ref.task_ms[0][i], 0) << i;
    }
    EXPECT_NEAR(dev.task_ms[0][i], (fd ? 0.5 : 1.0) * ref.task_ms[0][i], 1e-12) << i;
  }
  ASSERT_GT(ref.kernel_ms[0][0], 0);
  EXPECT_NEAR(dev.kernel_ms[0][0], 8 * ref.kernel_ms[0][0], 1e-12);
}

TEST(Coprocessor, TheBundledDevicesLoadAndTheAdrenoTakesTheMaxwellsEfficiency) {
  const Platform adreno = parse("name: p\ncoprocessor: {kind: gpu, device: adreno_530}\n");
  const Platform maxwell = parse("name: p\ncoprocessor: {kind: gpu, device: maxwell_tx1}\n");
  const Platform hexagon = parse("name: p\ncoprocessor: {kind: dsp, device: hexagon_680}\n");
  EXPECT_EQ(adreno.coprocessor->frame_setup_ms(), 40.0);  // the paper's launch/setup
  EXPECT_NEAR(hexagon.coprocessor->launch_ms(), 0.3, 1e-12);
  const nlohmann::json a = adreno.coprocessor->params_json();
  EXPECT_EQ(a["sparse_efficiency"], maxwell.coprocessor->params_json()["sparse_efficiency"]);
  EXPECT_THAT(a["sparse_efficiency_provenance"].get<std::string>(),
              HasSubstr("maxwell_tx1's: calibrated"));
  EXPECT_EQ(adreno.to_json()["coprocessor"]["kind"], "gpu");
  EXPECT_FALSE(parse("name: p\n").to_json().contains("coprocessor"));
  // A key beside the device overrides it; an efficiency given here replaces the shared one.
  const Platform own = parse(
      "name: p\ncoprocessor: {kind: gpu, device: adreno_530, sparse_efficiency: 0.5, "
      "frame_setup_ms: 1}\n");
  EXPECT_EQ(own.coprocessor->frame_setup_ms(), 1.0);
  EXPECT_EQ(own.coprocessor->params_json()["sparse_efficiency"], 0.5);
  EXPECT_EQ(own.coprocessor->params_json()["sparse_efficiency_of"], "");
}

TEST(Coprocessor, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("name: p\ncoprocessor:\n  kind: gpu\n  device: voodoo2\n"),
            "p.yaml:4: coprocessor.device: expected a bundled coprocessor (adreno_530, "
            "hexagon_680, maxwell_tx1), got 'voodoo2'");
  EXPECT_EQ(error_of("name: p\ncoprocessor:\n  kind: gpu\n  tasks: [FD, FC]\n"),
            "p.yaml:4: coprocessor.tasks: expected rows a gpu runs, got 'FC', bound by scalar "
            "work");
  EXPECT_EQ(error_of("name: p\ncoprocessor:\n  kind: dsp\n  kernels: [kalman_gain]\n"),
            "p.yaml:4: coprocessor.kernels: expected rows a dsp runs, got 'kalman_gain', bound "
            "by fp64 work");
  EXPECT_THAT(error_of("name: p\ncoprocessor:\n  kind: gpu\n  tasks: [XX]\n"),
              HasSubstr("coprocessor.tasks: expected frontend tasks names edx knows"));
  EXPECT_THAT(error_of("name: p\ncoprocessor:\n  kind: dsp\n  device: adreno_530\n"),
              HasSubstr("adreno_530.yaml:4: kind: expected 'dsp' (the kind that reads it), got "
                        "'gpu'"));
  EXPECT_THAT(error_of("name: p\ncoprocessor:\n  device: adreno_530\n"),
              HasSubstr("coprocessor.kind: expected one of dsp or gpu, got ''"));
  EXPECT_EQ(error_of("name: p\ncoprocessor:\n  kind: gpu\n  reference: cortex_a57_tx1\n"),
            "p.yaml:4: coprocessor.reference: expected an anchor processor (one with suite "
            "times), got 'cortex_a57_tx1', itself predicted");
  EXPECT_EQ(error_of("name: p\ncoprocessor:\n  kind: gpu\n  launch_us: -1\n"),
            "p.yaml:4: coprocessor.launch_us: expected a number in [0, 1000000], got '-1'");
}

TEST(Coprocessor, TheBaselinesFrontendAndBackendByHand) {
  // The Kaby Lake with a GPU that runs FD (each 1 ms launch) and kalman_gain, 5 ms setup a frame.
  const Platform p = parse(
      "name: p\nhost: {kind: datasheet, processor: kaby_lake_4c}\n"
      "coprocessor: {kind: gpu, clock_ghz: 1, int16_ops_per_cycle: 76.8, "
      "fp64_flops_per_cycle: 3.2, tasks: [FD], kernels: [kalman_gain], launch_us: 1000, "
      "frame_setup_ms: 5}\n");
  const std::vector<trace::FrameTrace> frames = {hand_frame("kalman_gain", 4'000'000)};
  const PlatformHostTimes host = p.host->host_times(frames, hand_meta(), "hand.db");
  const PlatformHostTimes dev = p.coprocessor->device_times(frames, hand_meta(), "hand.db");
  std::vector<double> tasks = host.task_ms[0];
  std::vector<bool> on_device(tasks.size(), false);
  double task_sum = 0;
  for (double ms : host.task_ms[0]) task_sum += ms;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (frames[0].tasks[i].task != trace::Task::FD) continue;
    tasks[i] = dev.task_ms[0][i] + 1.0;
    on_device[i] = true;
  }
  StageChains chains =
      chain_times(frames[0].tasks, tasks, host.frontend_ms[0] - task_sum, on_device);
  chains.insert(chains.begin(), {ChainTime{0, 5}});
  const double frontend = frontend_latency_ms(chains, 4);
  const double backend = host.backend_ms[0] - host.kernel_ms[0][0] + dev.kernel_ms[0][0] + 1.0;
  for (SystemModelKind model : {SystemModelKind::kAnalytical, SystemModelKind::kDes}) {
    SystemSimOptions options;
    options.model = model;
    const SystemResult r = simulate_system(p, frames, hand_meta(), "hand.db", options);
    const FrameResult& b = r.baseline.frames[0];
    EXPECT_NEAR(b.frontend_ms, frontend, 1e-9) << to_string(model);
    EXPECT_NEAR(b.backend_ms, backend, 1e-9) << to_string(model);
  }
  // Stage 1's two detections wait for each other on the device: more than either alone.
  EXPECT_GT(frontend, 5 + 2 * 1.0);
}

}  // namespace
}  // namespace edx::arch
