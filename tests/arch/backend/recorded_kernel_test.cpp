// The backend model on ops recorded by the real VIO backend: the Kalman gain of
// workloads/backend/vio/ekf_update.cpp, recorded through KernelRecorder, replays to the same ops
// (kind, sizes, flags) that kernel_ops() derives from the kernel's sizes alone.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "arch/backend/kernel_replay.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/ekf_update.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

TEST(BackendRecordedKernel, VioKalmanGainOpsMatchTheDerivationRule) {
  constexpr int kRows = 40, kState = 27;  // H is 40 x 27
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd J(kState, kState), H(kRows, kState);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = normal(rng);
  for (Eigen::Index i = 0; i < H.size(); ++i) H.data()[i] = normal(rng);
  const Eigen::MatrixXd P = J * J.transpose() + Eigen::MatrixXd::Identity(kState, kState);

  backend::KernelRecorder recorder;
  {
    auto kernel = recorder.kernel("kalman_gain", /*accelerable=*/true);
    kernel.record().m = kRows;
    kernel.record().n = kState;
    const backend::vio::KalmanGain gain =
        backend::vio::kalman_gain(P, H, Eigen::VectorXd::Constant(kRows, 0.25), &recorder);
    ASSERT_TRUE(gain.ok);
  }
  const std::vector<trace::KernelRecord> kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  const trace::KernelRecord& recorded = kernels[0];
  trace::KernelRecord sizes_only = recorded;
  sizes_only.ops.clear();

  const BackendConfig config;
  const std::vector<trace::OpRecord> derived = kernel_ops(sizes_only, config);
  ASSERT_EQ(recorded.ops.size(), derived.size());
  for (std::size_t i = 0; i < derived.size(); ++i) {
    EXPECT_EQ(recorded.ops[i].op, derived[i].op) << i;
    EXPECT_EQ(recorded.ops[i].m, derived[i].m) << i;
    EXPECT_EQ(recorded.ops[i].n, derived[i].n) << i;
    EXPECT_EQ(recorded.ops[i].k, derived[i].k) << i;
    EXPECT_EQ(recorded.ops[i].flags, derived[i].flags) << i;
  }
  const KernelAccelResult a = accelerate_kernel(recorded, config);
  const KernelAccelResult b = accelerate_kernel(sizes_only, config);
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_GT(a.cycles, 0);
  // S (40 x 40 of 27) is the symmetric result: ⌈40 / 4⌉ = 10 tile rows, so the 55 tiles on and
  // above the diagonal (not all 100), each 27 + 2 x 4 cycles.
  EXPECT_EQ(config.unit_for(trace::Op::Gemm)->unit->tile(), 4);
  EXPECT_EQ(a.ops[1].cycles, 55 * (kState + 2 * 4));
}

}  // namespace
}  // namespace edx::arch

namespace edx::arch {
namespace {

// The kernels beyond the paper's three record their ops in the trace (issue 40): on the
// reference trace, every Schur complement's, covariance update's and covariance propagation's
// recorded ops are those their descriptors derive from the kernel's sizes, and every GPS
// fusion's are whole fused fixes.
TEST(BackendRecordedKernel, TheReferenceTracesNewKernelsRecordTheirDerivedOps) {
  const std::string golden = std::string(EDX_SOURCE_DIR) + "/tests/data/golden/golden_mix.db";
  const std::vector<trace::FrameTrace> frames = trace::TraceReader(golden).read_all();
  const BackendConfig config;
  std::map<std::string, int> checked;
  for (const trace::FrameTrace& frame : frames) {
    for (const trace::KernelRecord& k : frame.kernels) {
      if (k.kernel != "schur_complement" && k.kernel != "covariance_update" &&
          k.kernel != "covariance_propagation" && k.kernel != "gps_fusion") {
        continue;
      }
      // A GPS fusion that fused no fix ran no matrix op.
      if (k.kernel == "gps_fusion" && k.ops.empty()) continue;
      ASSERT_FALSE(k.ops.empty()) << k.kernel << " in frame " << frame.frame.frame_id;
      trace::KernelRecord sizes_only = k;
      sizes_only.ops.clear();
      if (k.kernel == "gps_fusion") {
        // 8 ops a fused fix (the 3-row gain's 6 and the update's 2), at most one a fix.
        EXPECT_EQ(k.ops.size() % 8, 0u);
        EXPECT_LE(k.ops.size() / 8, static_cast<std::size_t>(k.m));
      } else {
        const std::vector<trace::OpRecord> derived = kernel_ops(sizes_only, config);
        ASSERT_EQ(k.ops.size(), derived.size()) << k.kernel;
        for (std::size_t i = 0; i < derived.size(); ++i) {
          EXPECT_EQ(k.ops[i].op, derived[i].op) << k.kernel << " op " << i;
          EXPECT_EQ(k.ops[i].m, derived[i].m) << k.kernel << " op " << i;
          EXPECT_EQ(k.ops[i].n, derived[i].n) << k.kernel << " op " << i;
          EXPECT_EQ(k.ops[i].k, derived[i].k) << k.kernel << " op " << i;
          EXPECT_EQ(k.ops[i].flags, derived[i].flags) << k.kernel << " op " << i;
          EXPECT_EQ(k.ops[i].batch, derived[i].batch) << k.kernel << " op " << i;
        }
      }
      ++checked[k.kernel];
    }
  }
  EXPECT_GT(checked["schur_complement"], 10);
  EXPECT_GT(checked["covariance_update"], 10);
  EXPECT_GT(checked["covariance_propagation"], 10);
  EXPECT_GT(checked["gps_fusion"], 0);
}

}  // namespace
}  // namespace edx::arch
