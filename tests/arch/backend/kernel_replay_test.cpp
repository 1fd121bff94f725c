// Kernel replay on the backend accelerator (arch/backend/kernel_replay.hpp).
#include "arch/backend/kernel_replay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "tests/arch/backend/backend_test_support.hpp"

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;
using testing::kalman_gain;
using trace::Op;
using trace::OpRecord;

BackendConfig small_config() { return testing::small_config(100.0); }

TEST(BackendKernelReplay, KalmanGainIsTheSumOfItsOps) {
  const BackendConfig c = small_config();
  const trace::KernelRecord k = kalman_gain(10, 8);
  const KernelAccelResult r = accelerate_kernel(k, c);
  // By hand (b = 4, 2b = 8):
  //   P H^T 8x10x8, P symmetric, result not square: 2 x 3 tiles x 16         =  96
  //   S 10x10x8 symmetric result: 6 upper tiles x 16                         =  96
  //   potrf 10: (1000-10)/6 + 45 = 210 MACs / 4 = 53 (⌈52.5⌉) + 10 x 15      = 203
  //   trsm 10x8 (twice): 10 + 9 + 10 + ⌈8 x 55 / 2⌉ = 29 + 220               = 249
  //   transpose 10x8: 80 / 2                                                 =  40
  ASSERT_EQ(r.ops.size(), 6u);
  EXPECT_EQ(r.ops[0].cycles, 96);
  EXPECT_EQ(r.ops[1].cycles, 96);
  EXPECT_EQ(r.ops[2].cycles, 203);
  EXPECT_EQ(r.ops[3].cycles, 249);
  EXPECT_EQ(r.ops[4].cycles, 249);
  EXPECT_EQ(r.ops[5].cycles, 40);
  EXPECT_EQ(r.cycles, 96 + 96 + 203 + 249 + 249 + 40);
  EXPECT_EQ(r.cycles, kernel_cycles(k, c));
  EXPECT_DOUBLE_EQ(r.compute_s, static_cast<double>(r.cycles) / 100e6);
  // Each op starts when the previous one ends.
  std::int64_t start = 0;
  for (const OpTiming& t : r.ops) {
    EXPECT_EQ(t.start_cycle, start);
    start += t.cycles;
  }
  const auto busy = [&](const std::string& unit) {
    return r.unit_busy_cycles[testing::unit_index(c, unit)];
  };
  EXPECT_EQ(busy("gemm"), 192);
  EXPECT_EQ(busy("decomposition"), 203);
  EXPECT_EQ(busy("substitution"), 498);
  EXPECT_EQ(busy("transpose"), 40);
  EXPECT_EQ(busy("inverse"), 0);
  EXPECT_FALSE(r.derived_ops);
  // The largest operand set: S = H (P H^T): H 80 + P H^T 80 + sym(10) 55 doubles (P H^T
  // takes 36 + 80 + 80, potrf 55, trsm 55 + 80, transpose 160).
  EXPECT_EQ(r.local_bytes, 215 * 8);
  EXPECT_TRUE(r.fits_local_memory);
  // The work by resource (the five units, all present): a busy copy-cycle is the unit's MAC
  // lanes (the 4x4 array's 16), in double precision; each op's SPM bytes go to its unit.
  ASSERT_EQ(r.activity.size(), 5u);
  EXPECT_DOUBLE_EQ(r.activity[0].double_macs, 192.0 * 16);
  EXPECT_DOUBLE_EQ(r.activity[0].single_macs, 0.0);
  EXPECT_DOUBLE_EQ(r.activity[2].double_macs, 0.0);  // no inverse
  double bram = 0;
  for (const cost::FrameActivity& a : r.activity) bram += a.bram_bytes;
  std::int64_t spm = 0;
  for (const OpTiming& t : r.ops) spm += t.spm_bytes;
  EXPECT_DOUBLE_EQ(bram, double(spm));
  EXPECT_DOUBLE_EQ(r.activity[3].bram_bytes, double(r.ops[5].spm_bytes));  // the transpose
}

TEST(BackendKernelReplay, DerivedOpsMatchRecordedOnes) {
  const BackendConfig c = small_config();
  trace::KernelRecord recorded = kalman_gain(12, 9);
  trace::KernelRecord sizes_only = recorded;
  sizes_only.ops.clear();
  const KernelAccelResult a = accelerate_kernel(recorded, c);
  const KernelAccelResult b = accelerate_kernel(sizes_only, c);
  EXPECT_TRUE(b.derived_ops);
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_EQ(a.local_bytes, b.local_bytes);
}

TEST(BackendKernelReplay, ProjectionWithoutOpsIsOneGemm) {
  const BackendConfig c = small_config();
  trace::KernelRecord k;
  k.kernel = "projection";
  k.accelerable = true;
  k.m = 100;  // map points
  const KernelAccelResult r = accelerate_kernel(k, c);
  ASSERT_EQ(r.ops.size(), 1u);
  EXPECT_EQ(r.ops[0].op.op, Op::Gemm);
  EXPECT_EQ(r.ops[0].op.m, 3);
  EXPECT_EQ(r.ops[0].op.n, 100);
  EXPECT_EQ(r.ops[0].op.k, 4);
  // ⌈3/4⌉ x ⌈100/4⌉ = 25 tiles of 4 + 8 cycles.
  EXPECT_EQ(r.cycles, 300);
  // C 12 + X 400 + result 300 doubles.
  EXPECT_EQ(r.local_bytes, 712 * 8);
}

TEST(BackendKernelReplay, MarginalizationWithoutOpsFollowsTheSlamBackend) {
  BackendConfig c = small_config();
  trace::KernelRecord k;
  k.kernel = "marginalization";
  k.accelerable = true;
  k.m = 4;   // landmarks, one inverse depth each: A_mm is 4 + 6 = 10 square
  k.n = 12;  // kept state
  const KernelAccelResult r = accelerate_kernel(k, c);
  ASSERT_EQ(r.ops.size(), 8u);
  EXPECT_EQ(r.ops[0].op.op, Op::Inverse);
  EXPECT_EQ(r.ops[0].op.m, 10);
  EXPECT_EQ(r.ops[0].cycles, 366);  // the structured 10x10 of op_timing_test
  EXPECT_EQ(r.ops[5].op.op, Op::Ldlt);
  EXPECT_EQ(r.ops[5].op.m, 12);
  std::int64_t sum = 0;
  for (const OpTiming& t : r.ops) sum += t.cycles;
  EXPECT_EQ(r.cycles, sum);
  k.n = 0;  // nothing kept: only the inverse
  EXPECT_EQ(accelerate_kernel(k, c).ops.size(), 1u);
}

TEST(BackendKernelReplay, UnitsOnTheirOwnClocks) {
  // kalman_gain 10 x 8 with the substitution unit at 50 MHz: its 498 cycles take 9.96 µs, the
  // other 435 at 100 MHz 4.35 µs.
  BackendConfig c = small_config();
  c.units[testing::unit_index(c, "substitution")].clock_mhz = 50;
  const KernelAccelResult r = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_EQ(r.cycles, 933);
  EXPECT_NEAR(r.compute_s, 435 / 100e6 + 498 / 50e6, 1e-18);
}

TEST(BackendKernelReplay, AKernelWithAnOpNoUnitServesStaysOnTheHost) {
  BackendConfig c = small_config();
  c.units[testing::unit_index(c, "transpose")].count = 0;
  const KernelAccelResult r = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_FALSE(r.runnable);
  EXPECT_TRUE(std::isinf(r.compute_s));
  EXPECT_NE(r.message.find("no backend unit serves its transpose op"), std::string::npos)
      << r.message;
  EXPECT_FALSE(offloadable(kalman_gain(10, 8), c));
  EXPECT_TRUE(offloadable(kalman_gain(10, 8), small_config()));
}

TEST(BackendKernelReplay, UnknownKernelWithoutOpsThrows) {
  trace::KernelRecord k;
  k.kernel = "pnp";
  EXPECT_THROW(accelerate_kernel(k, BackendConfig{}), std::runtime_error);
}

TEST(BackendKernelReplay, SpmOverflowIsFlaggedWithKernelBytesAndCapacity) {
  BackendConfig c = small_config();
  c.spm_bytes = 1000;
  const KernelAccelResult r = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_FALSE(r.fits_local_memory);
  EXPECT_EQ(r.local_bytes, 1720);
  EXPECT_NE(r.message.find("kalman_gain"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("1720 B"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("capacity 1000 B"), std::string::npos) << r.message;
  c.spm_bytes = 1720;  // exactly enough
  EXPECT_TRUE(accelerate_kernel(kalman_gain(10, 8), c).fits_local_memory);
  // Without the symmetric optimization S takes 100 doubles instead of 55.
  c.symmetric_optimization = false;
  const KernelAccelResult full = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_EQ(full.local_bytes, 260 * 8);
  EXPECT_FALSE(full.fits_local_memory);
}

TEST(BackendKernelReplay, SpillingOpsStreamTheirTilesFromDram) {
  // SPM 1000 B = 125 doubles: tile t = ⌊√(125/3)⌋ = 6 (3·36 = 108 <= 125 < 3·49).
  BackendConfig c = small_config();
  c.spm_bytes = 1000;
  EXPECT_EQ(spill_tile(c), 6);
  // A 12x12x12 gemm needs 3·144 doubles (3456 B): W = 1728 MACs, 2W/t = 576 doubles read (A and
  // B each read ⌈12/6⌉ = 2 times: the blocked count), the 144 results written once.
  const OpRecord gemm{Op::Gemm, 12, 12, 12, 0, 0};
  EXPECT_EQ(op_spill_traffic(gemm, c).read_bytes, 576 * 8);
  EXPECT_EQ(op_spill_traffic(gemm, c).write_bytes, 144 * 8);
  // A transpose of 10x8 (1280 B) does no MACs: each operand read once, each result written once.
  EXPECT_EQ(op_spill_traffic(OpRecord{Op::Transpose, 10, 8, 0, 0, 0}, c).read_bytes, 80 * 8);
  EXPECT_EQ(op_spill_traffic(OpRecord{Op::Transpose, 10, 8, 0, 0, 0}, c).write_bytes, 80 * 8);
  // What fits does not spill.
  EXPECT_EQ(op_spill_traffic(OpRecord{Op::Potrf, 10, 10, 0, 0, 0}, c).bytes(), 0);

  // kalman_gain(10, 8) on it, by hand (in, out, W, ⌈2W/6⌉ in doubles):
  //   P Hᵀ 8x10x8 (1568 B): in sym(8) + 80 = 116, out 80, W 640, 214 -> read 214
  //   S 10x10x8 symmetric (1720 B): in 160, out 55, W 8·55 = 440, 147 -> read 160
  //   potrf 10 (440 B) fits
  //   trsm 10x8 twice (1080 B): in 55 + 80 = 135, out 80, W 8·55 = 440, 147 -> read 147
  //   transpose 10x8 (1280 B): in 80, out 80, W 0 -> read 80
  const KernelAccelResult r = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_FALSE(r.fits_local_memory);
  EXPECT_EQ(r.spilled_ops, 5);
  EXPECT_EQ(r.spill.read_bytes, (214 + 160 + 147 + 147 + 80) * 8);
  EXPECT_EQ(r.spill.write_bytes, (80 + 55 + 80 + 80 + 80) * 8);
  EXPECT_EQ(r.ops[2].spill.bytes(), 0);
  // The units take the same cycles in or out of core.
  EXPECT_EQ(r.cycles, accelerate_kernel(kalman_gain(10, 8), small_config()).cycles);
  EXPECT_NE(r.message.find("5 op(s) spill, 5984 B read from and 3000 B written to DRAM"),
            std::string::npos)
      << r.message;
}

TEST(BackendKernelReplay, SpillTimeIsTheTrafficOnTheLink) {
  // The 12x12x12 gemm above: 4608 B read, 1152 B written, each a transfer on an idle PCIe link
  // (setup 1 µs + bytes / 7.9 GB/s + latency 0.5 µs: its 8 request slots never limit).
  BackendConfig c = small_config();
  c.spm_bytes = 1000;
  const KernelAccelResult r =
      accelerate_kernel(testing::kernel_of("gemm", {OpRecord{Op::Gemm, 12, 12, 12, 0, 0}}), c);
  const auto link = make_component<Link>("dma", "{preset: pcie3_x8}", "link");
  const double expected_ns = (1000 + 4608 / 7.9 + 500) + (1000 + 1152 / 7.9 + 500);
  EXPECT_NEAR(spill_seconds(r, *link), expected_ns * 1e-9, 2e-12);
  c.spm_bytes = 3456;  // exactly fits: no spill
  EXPECT_EQ(
      spill_seconds(
          accelerate_kernel(testing::kernel_of("gemm", {OpRecord{Op::Gemm, 12, 12, 12, 0, 0}}), c),
          *link),
      0.0);
}

}  // namespace
}  // namespace edx::arch
