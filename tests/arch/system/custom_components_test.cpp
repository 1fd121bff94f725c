// Issue 40's "adding a kind is one source file plus its registration", for the link and the
// on-chip memory: a link kind (tests/arch/link/kinds/ideal_link.cpp) and a memory kind
// (tests/arch/memory/kinds/fixed_block.cpp), each one file registering itself, named by a
// platform file and simulated end to end. Their figures are computed by hand from their own
// formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "arch/system/system_model.hpp"
#include "tests/arch/system/hand_tasks.hpp"

namespace edx::arch {
namespace {

/// The hand-built platform of custom_units_test with the new kinds: an ideal link of 1 us a
/// transfer at 2 pJ a byte, and memory blocks of 4096 bytes at 3 pJ a byte.
Platform custom_platform() {
  return Platform::parse(
      "name: custom\n"
      "host: {times: measured, frontend_suite_ms: 10.0, backend_suite_ms: 8.0}\n"
      "backend:\n"
      "  clock_mhz: 100\n"
      "  spm_bytes: 1048576\n"
      "link: {kind: ideal, latency_ns: 1000, pj_per_byte: 2}\n"
      "memory: {kind: fixed_block, bytes_per_block: 4096, pj_per_byte: 3}\n"
      "scheduler: {policy: always, training_fraction: 0}\n",
      "custom.yaml");
}

std::vector<trace::FrameTrace> one_frame() { return {hand_frame()}; }

const trace::TraceMeta kMeta = hand_meta();

TEST(CustomComponents, ANewLinkKindAndMemoryKindSimulateEndToEnd) {
  const Platform p = custom_platform();
  EXPECT_EQ(p.link->kind(), "ideal");
  EXPECT_EQ(p.memory->kind(), "fixed_block");
  // Both kinds are in the platform's JSON (and so in its config hash) with their parameters.
  EXPECT_EQ(p.to_json()["link"]["latency_ns"], 1000.0);
  EXPECT_EQ(p.to_json()["memory"]["bytes_per_block"], 4096);

  const SystemResult r = simulate_system(p, one_frame(), kMeta, "custom.db");
  // The projection's operands and results cross the ideal link in 1 us each, whatever their size.
  ASSERT_EQ(r.decisions.size(), 1u);
  EXPECT_TRUE(r.decisions[0].offloaded);
  EXPECT_NEAR(r.decisions[0].transfer_ms, 2 * 1e-3, 1e-15);
  // The backend's 1 MiB SPM in 4096-byte blocks: 256 blocks, no read muxes (the bram kind would
  // add LUTs for its stacked rows).
  bool found = false;
  for (const cost::CostEntry& e : r.resources.entries) {
    if (e.name != "backend_spm") continue;
    found = true;
    EXPECT_DOUBLE_EQ(e.shared.bram, 256.0);
    EXPECT_DOUBLE_EQ(e.shared.lut, 0.0);
  }
  EXPECT_TRUE(found);
  // Each frontend memory: ceil(W D / 32768 bits) blocks a copy.
  ASSERT_FALSE(r.frontend.memory.bram.structures.empty());
  for (const StructureUsage& u : r.frontend.memory.bram.structures) {
    const double bits = double(u.structure.width_bits) * double(u.structure.depth_words);
    EXPECT_DOUBLE_EQ(u.blocks, std::ceil(bits / 32768.0) * double(u.structure.count))
        << u.structure.name;
  }
  // A frame's bytes cost the kinds' energies: 3 pJ an on-chip byte, 2 pJ a link byte.
  for (const FrameResult& f : r.accelerated.frames) {
    EXPECT_GT(f.activity.link_bytes, 0.0);
    EXPECT_GT(f.activity.bram_bytes, 0.0);
    EXPECT_NEAR(f.energy.link_j, f.activity.link_bytes * 2e-12, 1e-18);
    EXPECT_NEAR(
        f.energy.memory_j,
        (f.activity.bram_bytes * 3.0 + f.activity.dram_bytes * p.power.dram_pj_per_byte) * 1e-12,
        1e-18);
  }
}

TEST(CustomComponents, TheKindsRefuseKeysOfOtherKinds) {
  EXPECT_THROW(Platform::parse("name: x\nlink: {kind: ideal, bandwidth_gb_per_s: 2}\n", "x.yaml"),
               std::runtime_error);
  EXPECT_THROW(
      Platform::parse("name: x\nmemory: {kind: fixed_block, allow_bram18: false}\n", "x.yaml"),
      std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
