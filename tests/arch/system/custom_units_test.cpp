// Issue 40's "adding a unit kind is one source file plus its registration": a backend unit kind
// (custom_units/vector_mac.cpp) and a frontend unit kind (custom_units/harris_detector.cpp), each
// one file registering itself, used by a platform file and simulated end to end. Their figures
// are computed by hand from their own formulas.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "arch/frontend/task_timing.hpp"
#include "arch/system/system_model.hpp"
#include "tests/arch/backend/backend_test_support.hpp"
#include "tests/arch/system/hand_tasks.hpp"

namespace edx::arch {
namespace {

/// The hand-built platform of system_model_test with the new kinds in two instances: the gemm
/// unit a 4-lane MAC vector of depth 6, FD a Harris detector at 1 pixel a cycle, window 5.
Platform custom_platform(int fd_copies) {
  return Platform::parse(
      "name: custom\n"
      "host: {times: measured, frontend_suite_ms: 10.0, backend_suite_ms: 8.0}\n"
      "frontend:\n"
      "  units:\n"
      "    FD: {kind: harris_detector, pixels_per_cycle: 1, window: 5, count: " +
          std::to_string(fd_copies) +
          "}\n"
          "backend:\n"
          "  clock_mhz: 100\n"
          "  spm_bytes: 67108864\n"
          "  units:\n"
          "    gemm: {kind: vector_mac, lanes: 4, depth: 6}\n"
          "link:\n  bandwidth_gb_per_s: 1.0\n  latency_ns: 100\n"
          "  dma: {setup_ns: 100, chunk_bytes: 4194304, max_outstanding: 1}\n"
          "scheduler: {policy: always, training_fraction: 0}\n",
      "custom.yaml");
}

std::vector<trace::FrameTrace> one_frame() { return {hand_frame()}; }

const trace::TraceMeta kMeta = hand_meta();

TEST(CustomUnits, ANewBackendKindAndFrontendKindSimulateEndToEnd) {
  const Platform p = custom_platform(1);
  EXPECT_EQ(testing::fpga_config(*p.backend).units[0].unit->kind(), "vector_mac");
  EXPECT_EQ(p.frontend.unit(trace::Task::FD).unit->kind(), "harris_detector");
  // Both kinds are in the platform's JSON (and so in its config hash) with their parameters.
  EXPECT_EQ(p.to_json()["backend"]["units"]["gemm"]["lanes"], 4);
  EXPECT_EQ(p.to_json()["frontend"]["units"]["FD"]["window"], 5);

  // FD: 1000 pixels of a 40-wide level plus the 5x5 window's halo (2 lines + 2 pixels) at one
  // pixel a cycle: 1082 cycles.
  const std::vector<trace::FrameTrace> frames = one_frame();
  EXPECT_EQ(task_cycles(frames[0].tasks[0], 1000, p.frontend), 1082);

  const SystemResult r = simulate_system(p, frames, kMeta, "custom.db");
  // FE: the left and right FD on the one detector, one after the other (FC has no keypoints):
  // 2 x 1082 cycles at the frontend's 150 MHz.
  const sim::ClockDomain fe_clock("frontend", 150);
  EXPECT_NEAR(r.frontend.fe_ms.mean, sim::to_ms(fe_clock.time_of_cycles(2164)), 1e-12);
  // The projection on the MAC vector: ⌈1200 / 4⌉ + 6 = 306 cycles at 100 MHz.
  ASSERT_EQ(r.decisions.size(), 1u);
  EXPECT_TRUE(r.decisions[0].offloaded);
  EXPECT_NEAR(r.decisions[0].compute_ms, 306 / 100e6 * 1e3, 1e-15);
  // Their resources: four double MACs (PG060: 11 + 3 DSP each); 25 8x8-bit products (one DSP
  // each) of the detector.
  for (const cost::CostEntry& e : r.resources.entries) {
    if (e.name == "gemm") {
      EXPECT_DOUBLE_EQ(e.shared.dsp, 4 * 14.0);
    }
    if (e.name == "FD") {
      EXPECT_DOUBLE_EQ(e.shared.dsp, 25.0);
    }
  }
  // Both are resources of the whole-system DES, with their energy.
  std::vector<std::string> names;
  for (const cost::ResourceEnergy& e : r.accelerated.stream->energy_by_resource) {
    names.push_back(e.name);
  }
  EXPECT_NE(std::find(names.begin(), names.end(), "backend.gemm"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "frontend.FD"), names.end());
}

TEST(CustomUnits, TwoDetectorCopiesRunTheLeftAndRightImagesSideBySide) {
  const SystemResult r = simulate_system(custom_platform(2), one_frame(), kMeta, "custom.db");
  const sim::ClockDomain fe_clock("frontend", 150);
  EXPECT_NEAR(r.frontend.fe_ms.mean, sim::to_ms(fe_clock.time_of_cycles(1082)), 1e-12);
  // Two copies cost twice one.
  double fd_dsp = 0;
  for (const cost::CostEntry& e : r.resources.entries) {
    if (e.name == "FD") fd_dsp = e.shared.dsp;
  }
  EXPECT_DOUBLE_EQ(fd_dsp, 2 * 25.0);
}

}  // namespace
}  // namespace edx::arch
