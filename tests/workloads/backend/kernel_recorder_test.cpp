#include "workloads/backend/kernel_recorder.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <stdexcept>
#include <thread>

#include "workloads/trace/host_clock.hpp"

namespace edx::backend {
namespace {

TEST(KernelRecorder, RecordsKernelsAndOpsInOrderWithTimes) {
  KernelRecorder recorder;
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(40, 30);
  {
    auto kernel = recorder.kernel("kalman_gain", true);
    kernel.record().m = 40;
    const Eigen::MatrixXd s = recorder.op(trace::Op::Syrk, 40, 40, 30, trace::op_flags::kSymmetric,
                                          [&] { return (a * a.transpose()).eval(); });
    EXPECT_EQ(s.rows(), 40);
    // Host times are the thread's CPU time: 2 ms of work count, a sleep would not.
    recorder.op(trace::Op::Transpose, 40, 30, 0, 0, [&] {
      const std::int64_t start = trace::thread_cpu_ns();
      volatile double x = 0;
      while (trace::thread_cpu_ns() - start < 2'000'000) x = x + 1;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      return 0;
    });
  }
  { auto kernel = recorder.kernel("imu_propagation"); }
  const auto kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 2u);
  EXPECT_EQ(kernels[0].kernel, "kalman_gain");
  EXPECT_TRUE(kernels[0].accelerable);
  EXPECT_EQ(kernels[0].m, 40);
  ASSERT_EQ(kernels[0].ops.size(), 2u);
  EXPECT_EQ(kernels[0].ops[0].op, trace::Op::Syrk);
  EXPECT_EQ(kernels[0].ops[0].k, 30);
  EXPECT_EQ(kernels[0].ops[0].flags, trace::op_flags::kSymmetric);
  EXPECT_GE(kernels[0].ops[1].host_ns, 2'000'000);
  EXPECT_LT(kernels[0].ops[1].host_ns, 4'000'000);  // not the 5 ms of sleep
  // The kernel's time covers its ops.
  EXPECT_GE(kernels[0].host_ns, kernels[0].ops[0].host_ns + kernels[0].ops[1].host_ns);
  EXPECT_EQ(kernels[1].kernel, "imu_propagation");
  EXPECT_FALSE(kernels[1].accelerable);
  EXPECT_TRUE(kernels[1].ops.empty());
  EXPECT_TRUE(recorder.take().empty());
}

TEST(KernelRecorder, RefusesNestedKernelsAndOpsOutsideKernels) {
  KernelRecorder recorder;
  EXPECT_THROW(recorder.op(trace::Op::Gemm, 1, 1, 1, 0, [] { return 0; }), std::logic_error);
  auto outer = recorder.kernel("marginalization", true);
  EXPECT_THROW((void)recorder.kernel("inner"), std::logic_error);
  EXPECT_THROW(recorder.take(), std::logic_error);
}

}  // namespace
}  // namespace edx::backend
