// The accelerable-kernel registry (arch/kernels): names, derived ops and operand bytes checked
// against hand-computed values.
#include "arch/kernels/kernels.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;
using trace::Op;

TEST(AccelerableKernels, RegistryNamesAndLookups) {
  ASSERT_EQ(accelerable_kernels().size(), 11u);
  EXPECT_EQ(accelerable_kernel_names(),
            "projection, kalman_gain, marginalization, schur_complement, covariance_update, "
            "gps_fusion, nullspace_projection, normal_equations, solve, compression or "
            "covariance_propagation");
  EXPECT_EQ(paper_offload_set(),
            (std::vector<std::string>{"projection", "kalman_gain", "marginalization"}));
  EXPECT_EQ(&accelerable_kernel("kalman_gain"), &kalman_gain_kernel());
  EXPECT_EQ(find_accelerable_kernel("pnp"), nullptr);
  try {
    accelerable_kernel("pnp");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "kernel 'pnp': expected an accelerable kernel (projection, kalman_gain, "
              "marginalization, schur_complement, covariance_update, gps_fusion, "
              "nullspace_projection, normal_equations, solve, compression or "
              "covariance_propagation)");
  }
  EXPECT_EQ(projection_kernel().host_model_degree, 1);
  EXPECT_EQ(kalman_gain_kernel().host_model_degree, 2);
  EXPECT_EQ(marginalization_kernel().mode, "slam");
}

TEST(AccelerableKernels, DerivedOpsFollowTheBackendsRecords) {
  const KernelMatrixFormat format{8, 6, 3};
  const auto projection = projection_kernel().derive_ops(100, 0, format);
  ASSERT_EQ(projection.size(), 1u);
  EXPECT_EQ(projection[0].op, Op::Gemm);
  EXPECT_EQ(projection[0].m, 3);
  EXPECT_EQ(projection[0].n, 100);
  EXPECT_EQ(projection[0].k, 4);

  const auto gain = kalman_gain_kernel().derive_ops(4, 10, format);
  ASSERT_EQ(gain.size(), 6u);
  EXPECT_EQ(gain[0].op, Op::Gemm);  // P Hᵀ: 10 x 4 over 10
  EXPECT_EQ(gain[0].m, 10);
  EXPECT_EQ(gain[0].n, 4);
  EXPECT_EQ(gain[0].flags, flags::kSymmetric | flags::kTransposeB);
  EXPECT_EQ(gain[2].op, Op::Potrf);
  EXPECT_EQ(gain[2].m, 4);
  EXPECT_EQ(gain[5].op, Op::Transpose);

  // 3 landmarks of 3 parameters and a 6-dof pose: A_mm is 15 x 15; 5 states kept.
  const auto marg = marginalization_kernel().derive_ops(3, 5, format);
  ASSERT_EQ(marg.size(), 8u);
  EXPECT_EQ(marg[0].op, Op::Inverse);
  EXPECT_EQ(marg[0].m, 15);
  EXPECT_EQ(marg[0].flags, flags::kDiagonalBlock | flags::kSymmetric | flags::kBlock6x6);
  EXPECT_EQ(marg[2].op, Op::Gemm);  // T = A_rm A_mm⁻¹: 5 x 15 over 15
  EXPECT_EQ(marg[2].m, 5);
  EXPECT_EQ(marg[2].n, 15);
  EXPECT_EQ(marg[2].k, 15);
  EXPECT_EQ(marginalization_kernel().derive_ops(3, 0, format).size(), 1u);  // r = 0: inverse
  // A pose that is not 6-dof has no 6x6 block.
  EXPECT_EQ(marginalization_kernel().derive_ops(3, 5, {8, 7, 3})[0].flags,
            flags::kDiagonalBlock | flags::kSymmetric);
}

TEST(AccelerableKernels, OperandBytesByHand) {
  const KernelMatrixFormat format{8, 6, 1};
  trace::KernelRecord gain;
  gain.kernel = "kalman_gain";
  gain.m = 4;
  gain.n = 10;
  const KernelOperands g = kalman_gain_kernel().operands(gain, format, true);
  EXPECT_EQ(g.inputs["H"], 4 * 10 * 8);
  EXPECT_EQ(g.inputs["P"], 55 * 8);  // sym(10) packed
  EXPECT_EQ(g.inputs["R"], 4 * 8);
  EXPECT_EQ(g.outputs["K"], 10 * 4 * 8);
  EXPECT_EQ(kalman_gain_kernel().operands(gain, format, false).inputs["P"], 100 * 8);

  // landmark_dim from the recorded A_mm inverse (3 x 3 + 6 = 15), over the configured 1.
  trace::KernelRecord marg;
  marg.kernel = "marginalization";
  marg.m = 3;
  marg.n = 5;
  marg.ops.push_back(trace::OpRecord{Op::Inverse, 15, 15, 0, 0, 0});
  const KernelOperands m = marginalization_kernel().operands(marg, format, true);
  EXPECT_EQ(m.inputs["A_mm.A"], 3 * 3 * 3 * 8);  // 3 blocks 3 x 3
  EXPECT_EQ(m.inputs["A_mm.B"], 9 * 6 * 8);      // d_l x p
  EXPECT_EQ(m.inputs["A_mm.D"], 21 * 8);         // sym(6)
  EXPECT_EQ(m.inputs["A_mr"], 15 * 5 * 8);       // d_m x n
  EXPECT_EQ(m.inputs["A_rr"], 15 * 8);           // sym(5)
  EXPECT_EQ(m.inputs["b_m"], 15 * 8);
  EXPECT_EQ(m.outputs["prior_H"], 15 * 8);
  EXPECT_EQ(m.outputs["prior_b"], 5 * 8);
  // A detail landmark_dim wins; a bad one is an error naming the kernel.
  marg.detail_json = R"({"landmark_dim": 2})";
  EXPECT_EQ(marginalization_kernel().operands(marg, format, true).inputs["A_mm.A"], 3 * 2 * 2 * 8);
  marg.detail_json = R"({"landmark_dim": 0})";
  EXPECT_THROW(marginalization_kernel().operands(marg, format, true), std::runtime_error);
}

TEST(AccelerableKernels, OperandBytesOfTheBatchedKernelsByHand) {
  const KernelMatrixFormat format{8, 6, 1};
  // Null-space projection: two features of 6 rows and one of 9 (qr batches), state 20, 10 rows
  // accepted: in H_x 21 x 20, H_f 21 x 3, r 21, P sym(20); out 10 x 20 and 10.
  trace::KernelRecord ns;
  ns.kernel = "nullspace_projection";
  ns.m = 10;
  ns.n = 20;
  ns.ops = {{Op::Qr, 6, 3, 0, 0, 0, 2}, {Op::Gemm, 3, 21, 6, 0, 0, 2}, {Op::Qr, 9, 3, 0, 0, 0, 1}};
  const KernelOperands p = nullspace_projection_kernel().operands(ns, format, true);
  EXPECT_EQ(p.inputs["H_x"], 21 * 20 * 8);
  EXPECT_EQ(p.inputs["H_f"], 21 * 3 * 8);
  EXPECT_EQ(p.inputs["r"], 21 * 8);
  EXPECT_EQ(p.inputs["P"], 210 * 8);
  EXPECT_EQ(p.outputs["H"], 10 * 20 * 8);
  EXPECT_EQ(p.outputs["r"], 10 * 8);
  // Normal equations: 100 terms, 60 across keyframes, C = 13, 30 landmarks, 70 coupling
  // blocks, 2 IMU factors, a 15 x 15 prior.
  trace::KernelRecord ne;
  ne.kernel = "normal_equations";
  ne.m = 100;
  ne.n = 13;
  ne.k = 60;
  ne.detail_json = R"({"landmarks": 30, "coupling_blocks": 70, "imu_factors": 2, "prior_rows": 15,)"
                   R"( "prior_cols": 15})";
  const KernelOperands q = normal_equations_kernel().operands(ne, format, true);
  EXPECT_EQ(q.inputs["terms"], 100 * 13 * 8);
  EXPECT_EQ(q.inputs["J_pose"], 60 * 48 * 8);
  EXPECT_EQ(q.inputs["imu"], 2 * 690 * 8);
  EXPECT_EQ(q.inputs["prior"], 15 * 16 * 8);
  EXPECT_EQ(q.outputs["H_cc"], 91 * 8);  // sym(13)
  EXPECT_EQ(q.outputs["b_c"], 13 * 8);
  EXPECT_EQ(q.outputs["H_ll_b_l_H_lo"], 90 * 8);
  EXPECT_EQ(q.outputs["H_lc"], 70 * 6 * 8);
  ne.detail_json = R"({"landmarks": -1})";
  EXPECT_THROW(normal_equations_kernel().operands(ne, format, true), std::runtime_error);
  // Solve: C = 13, 30 landmarks, 70 coupling dot products (gemm 1x1x6).
  trace::KernelRecord solve;
  solve.kernel = "solve";
  solve.m = 13;
  solve.n = 30;
  solve.ops = {{Op::Ldlt, 13, 13, 0, 0, 0}, {Op::Gemm, 1, 1, 6, 0, 0, 70}};
  const KernelOperands v = solve_kernel().operands(solve, format, false);
  EXPECT_EQ(v.inputs["S"], 169 * 8);
  EXPECT_EQ(v.inputs["H_lc"], 70 * 6 * 8);
  EXPECT_EQ(v.outputs["dx_l"], 30 * 8);
}

}  // namespace
}  // namespace edx::arch
