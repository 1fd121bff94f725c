// Kernel replay on the backend accelerator (arch/backend/kernel_replay.hpp).
#include "arch/backend/kernel_replay.hpp"

#include <gtest/gtest.h>

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
  EXPECT_DOUBLE_EQ(r.seconds, static_cast<double>(r.cycles) / 100e6);
  // Each op starts when the previous one ends.
  std::int64_t start = 0;
  for (const OpTiming& t : r.ops) {
    EXPECT_EQ(t.start_cycle, start);
    start += t.cycles;
  }
  EXPECT_EQ(r.busy_cycles(BackendUnit::kMultiply), 192);
  EXPECT_EQ(r.busy_cycles(BackendUnit::kDecompose), 203);
  EXPECT_EQ(r.busy_cycles(BackendUnit::kSubstitute), 498);
  EXPECT_EQ(r.busy_cycles(BackendUnit::kTranspose), 40);
  EXPECT_EQ(r.busy_cycles(BackendUnit::kInverse), 0);
  EXPECT_FALSE(r.derived_ops);
  // The largest operand set: S = H (P H^T): H 80 + P H^T 80 + sym(10) 55 doubles (P H^T
  // takes 36 + 80 + 80, potrf 55, trsm 55 + 80, transpose 160).
  EXPECT_EQ(r.spm_bytes_needed, 215 * 8);
  EXPECT_TRUE(r.fits_spm);
  EXPECT_EQ(r.spm.bytes, 215 * 8);
  EXPECT_EQ(r.spm.depth_words, 215);  // one double a 64-bit word
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
  EXPECT_EQ(a.spm_bytes_needed, b.spm_bytes_needed);
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
  EXPECT_EQ(r.spm_bytes_needed, 712 * 8);
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

TEST(BackendKernelReplay, PredictionFromSizesAlone) {
  const BackendConfig c = small_config();
  // projection of 100 map points: 300 cycles at 100 MHz = 3 µs.
  EXPECT_DOUBLE_EQ(predict_kernel_seconds("projection", 100, 0, c), 3e-6);
  // kalman_gain 10 x 8: the 933 cycles of the replay above.
  EXPECT_DOUBLE_EQ(predict_kernel_seconds("kalman_gain", 10, 8, c), 933 / 100e6);
  EXPECT_THROW(predict_kernel_seconds("pnp", 10, 8, c), std::runtime_error);
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
  EXPECT_FALSE(r.fits_spm);
  EXPECT_EQ(r.spm_bytes_needed, 1720);
  EXPECT_NE(r.message.find("kalman_gain"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("1720 B"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("capacity 1000 B"), std::string::npos) << r.message;
  c.spm_bytes = 1720;  // exactly enough
  EXPECT_TRUE(accelerate_kernel(kalman_gain(10, 8), c).fits_spm);
  // Without the symmetric optimization S takes 100 doubles instead of 55.
  c.symmetric_optimization = false;
  const KernelAccelResult full = accelerate_kernel(kalman_gain(10, 8), c);
  EXPECT_EQ(full.spm_bytes_needed, 260 * 8);
  EXPECT_FALSE(full.fits_spm);
}

TEST(BackendKernelReplay, OffloadEstimateAddsTheTransfers) {
  const BackendConfig c = small_config();
  const trace::KernelRecord k = kalman_gain(10, 8);
  const LinkSpec link = LinkSpec::pcie3_x8();
  const FrameTransferConfig transfers;
  const double transfer_s =
      sim::to_seconds(kernel_transfer_time(link, kernel_transfer(k, transfers, c.matrix_format())));
  EXPECT_GT(transfer_s, 0.0);
  EXPECT_DOUBLE_EQ(estimate_offload_seconds(k, c, link, transfers),
                   kernel_seconds(k, c) + transfer_s);
}

}  // namespace
}  // namespace edx::arch
