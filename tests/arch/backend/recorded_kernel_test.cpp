// The backend model on ops recorded by the real VIO backend: the Kalman gain of
// workloads/backend/vio/ekf_update.cpp, recorded through KernelRecorder, replays to the same ops
// (kind, sizes, flags) that kernel_ops() derives from the kernel's sizes alone.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "arch/backend/kernel_replay.hpp"
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/vio/ekf_update.hpp"

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
