// Resource primitives and unit cost functions against hand-computed counts (docs/MODEL.md).
#include "arch/cost/resources.hpp"

#include <gtest/gtest.h>

#include "arch/backend/accelerators/fpga_matrix_units.hpp"
#include "arch/backend/matrix_unit.hpp"
#include "arch/cost/resource_report.hpp"
#include "arch/frontend/task_timing.hpp"
#include "tests/arch/frontend/frontend_test_support.hpp"

namespace edx::arch::cost {
namespace {

TEST(Datapath, AdderTreeOfFourEightBitInputs) {
  Datapath d;
  // Level 1: two 9-bit adders; level 2: one 10-bit adder.
  EXPECT_EQ(d.adder_tree(1, 4, 8), 10);
  EXPECT_DOUBLE_EQ(d.resources().lut, 2 * 9 + 10);
  EXPECT_DOUBLE_EQ(d.resources().ff, 2 * 9 + 10);
  EXPECT_DOUBLE_EQ(d.resources().dsp, 0);
}

TEST(Datapath, AdderTreeOfAnOddCountCarriesTheLeftover) {
  Datapath d;
  // 9 inputs of 24 bits: 4 adders of 25, 2 of 26, 1 of 27, 1 of 28 bits.
  EXPECT_EQ(d.adder_tree(1, 9, 24), 28);
  EXPECT_DOUBLE_EQ(d.resources().lut, 4 * 25 + 2 * 26 + 27 + 28);
}

TEST(Datapath, PopcountOf256Bits) {
  Datapath d;
  d.popcounts(1, 256);
  // Σ_l (256 / 2^l) · l for l = 1..8.
  EXPECT_DOUBLE_EQ(d.resources().lut, 128 + 128 + 96 + 64 + 40 + 24 + 14 + 8);
}

TEST(Datapath, PrimitivesCostWhatTheTableSays) {
  Datapath d;
  d.comparators(2, 8).abs_diffs(1, 8).reductions(3, 9).xors(1, 7).muxes(1, 8, 10);
  // LUT: 16 + 16 + 3·⌈8/5⌉ + ⌈7/2⌉ + 8·⌈9/3⌉ = 16 + 16 + 6 + 4 + 24.
  EXPECT_DOUBLE_EQ(d.resources().lut, 66);
  // FF: 2 (comparator bits) + 8 (|a − b|) + 3 (reductions).
  EXPECT_DOUBLE_EQ(d.resources().ff, 13);
  d.multipliers(2, 8, 16).multipliers(1, 26, 20);  // 2·1 + ⌈26/25⌉·⌈20/18⌉ = 2 + 4
  EXPECT_DOUBLE_EQ(d.resources().dsp, 6);
}

TEST(Datapath, FloatingPointMacsTakePg060Operators) {
  Datapath d;
  d.macs(2, Arithmetic::kDouble);
  EXPECT_DOUBLE_EQ(d.resources().dsp, 2 * (11 + 3));
  EXPECT_DOUBLE_EQ(d.resources().lut, 2 * (208 + 1149));
  EXPECT_DOUBLE_EQ(d.resources().ff, 2 * (317 + 445));
  Datapath s;
  s.macs(1, Arithmetic::kSingle);
  EXPECT_DOUBLE_EQ(s.resources().dsp, 3 + 2);
  Datapath f;
  f.macs(3, Arithmetic::kFixed, 16, 16);
  EXPECT_DOUBLE_EQ(f.resources().dsp, 3);
  EXPECT_DOUBLE_EQ(f.resources().lut, 0);
}

/// The resources of one copy of the unit of `task` with `params` (YAML of its kind's keys).
Resources unit_cost(const FrontendConfig& fe, trace::Task task, const std::string& params) {
  FrontendConfig c = fe;
  testing::set_unit(c, task, params);
  return c.unit(task).unit->resources(c);
}

TEST(UnitCosts, HammingUnitByHand) {
  const FrontendConfig fe;
  const Resources r = unit_cost(fe, trace::Task::MO, "{comparators: 1}");
  // XOR 128 + popcount 502 + two 9-bit comparators 18.
  EXPECT_DOUBLE_EQ(r.lut, 128 + 502 + 18);
  // popcount 502 + comparators 2 + two descriptors 512 + 4 x (9 + 16) index/distance registers.
  EXPECT_DOUBLE_EQ(r.ff, 502 + 2 + 512 + 100);
  EXPECT_DOUBLE_EQ(r.dsp, 0);
  const Resources four = unit_cost(fe, trace::Task::MO, "{comparators: 4}");
  EXPECT_DOUBLE_EQ(four.lut, 4 * (128 + 502 + 18));
}

TEST(UnitCosts, GaussianThreeByThreeOnOneLane) {
  FrontendConfig fe;
  fe.fe_pixels_per_cycle = 1;
  fe.if_stencil = 3;
  const Resources r = unit_cost(fe, trace::Task::IF, "{arithmetic: fixed}");
  EXPECT_DOUBLE_EQ(r.dsp, 9);                          // k² products
  EXPECT_DOUBLE_EQ(r.lut, 4 * 25 + 2 * 26 + 27 + 28);  // tree of 9 24-bit products
  EXPECT_DOUBLE_EQ(r.ff, 207 + 3 * 3 * 8);             // tree + 3x3 window of pixels
  const std::string separable = "{arithmetic: fixed, separable: true}";
  EXPECT_DOUBLE_EQ(unit_cost(fe, trace::Task::IF, separable).dsp, 6);  // 2k taps
  fe.fe_pixels_per_cycle = 2;
  EXPECT_DOUBLE_EQ(unit_cost(fe, trace::Task::IF, separable).dsp, 12);  // two lanes
  // PG060 fmul + fadd per tap
  EXPECT_DOUBLE_EQ(unit_cost(fe, trace::Task::IF, "{arithmetic: single, separable: true}").dsp,
                   12 * (3 + 2));
}

TEST(UnitCosts, GemmTwoByTwoDoubleByHand) {
  const MatrixUnitInstance array = make_matrix_unit("gemm", "systolic_array", "{block: 2}");
  const Resources r = array.unit->resources(Arithmetic::kDouble);
  EXPECT_DOUBLE_EQ(r.dsp, 4 * 14);
  EXPECT_DOUBLE_EQ(r.lut, 4 * (208 + 1149) + 3 * 16);
  // MACs + operand registers 4·2·64 + input registers 2·2·64 + AGX 48.
  EXPECT_DOUBLE_EQ(r.ff, 4 * (317 + 445) + 512 + 256 + 48);
  // Single-precision MACs (backend.precision fp32).
  EXPECT_DOUBLE_EQ(array.unit->resources(Arithmetic::kSingle).dsp, 4 * 5);
  BackendConfig be;
  be.units = {array};
  be.units[0].count = 2;  // two arrays: twice the unit's resources in the report
  const ResourceReport report = build_resource_report(
      FrontendConfig{}, *fpga_matrix_units(be), CostConfig{},
      *ComponentRegistry<OnChipMemory>::instance().make("bram"), {}, Device::by_name("xc7v690t"));
  for (const CostEntry& e : report.entries) {
    if (e.name == "gemm") {
      EXPECT_DOUBLE_EQ(e.shared.dsp, 2 * 4 * 14);
    }
  }
}

TEST(UnitCosts, UnitsGrowWithTheirDimensions) {
  using trace::Task;
  FrontendConfig small, big;
  big.fe_pixels_per_cycle = 4;
  const auto cost_of = [](const FrontendConfig& fe, Task task) {
    return fe.unit(task).unit->resources(fe);
  };
  EXPECT_GT(cost_of(big, Task::FD).lut, cost_of(small, Task::FD).lut);
  EXPECT_GT(unit_cost(small, Task::FC, "{tests_per_cycle: 64}").lut, cost_of(small, Task::FC).lut);
  EXPECT_GT(unit_cost(small, Task::DR, "{sad_units: 22}").lut, cost_of(small, Task::DR).lut);
  EXPECT_GT(unit_cost(small, Task::LSS, "{macs_per_cycle: 128}").dsp,
            cost_of(small, Task::LSS).dsp);
  EXPECT_GT(cost_of(small, Task::FC).bram, 0);  // the rotated-pattern table
}

TEST(UnitCosts, LanesRoundUpFractionalRates) {
  EXPECT_EQ(lanes_of(0.25), 1);
  EXPECT_EQ(lanes_of(1.0), 1);
  EXPECT_EQ(lanes_of(2.0), 2);
  EXPECT_EQ(lanes_of(2.5), 3);
}

}  // namespace
}  // namespace edx::arch::cost
