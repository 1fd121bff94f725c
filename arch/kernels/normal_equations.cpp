// The normal equations of SLAM's Levenberg-Marquardt step (workloads/backend/slam/lm_solver.cpp
// form_normal_equations): H = Σ JᵀWJ and b = -Σ JᵀWr from the window's residuals and Jacobians
// (kernel "linearization", on the host). Not one of the paper's three accelerated kernels;
// offloadable when scheduler.offload names it (issue 40). Its ops are small products in batches
// (6x6 blocks of 4-row Jacobians): only the trace knows their counts (no derive_ops).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = N terms, k = X of them across keyframes, n = C camera-block columns; detail: landmarks
/// L, coupling_blocks B, imu_factors I, prior_rows P and prior_cols Q. In per term r, J_ρ, J_o
/// (4 each) and its weight, per cross term J_anchor and J_target (4 x 6 each), per IMU factor
/// r, W and J (15, 15 x 15, 15 x 30), the prior's J and r (P x Q, P); out H_cc C x C (sym), b_c
/// C, H_ll, b_l and H_lo (L each) and the couplings H_lc (6 a block).
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const auto detail = [&](const char* key) { return detail_integer(k, key).value_or(0); };
  const std::int64_t terms = k.m, cross = k.k, cameras = k.n, s = f.scalar_bytes;
  const std::int64_t landmarks = detail("landmarks"), imu = detail("imu_factors");
  const std::int64_t prior_rows = detail("prior_rows"), prior_cols = detail("prior_cols");
  KernelOperands o;
  o.inputs["terms"] = terms * (3 * 4 + 1) * s;
  o.inputs["J_pose"] = cross * 2 * 4 * 6 * s;
  o.inputs["imu"] = imu * (15 + 15 * 15 + 15 * 30) * s;
  o.inputs["prior"] = prior_rows * (prior_cols + 1) * s;
  o.outputs["H_cc"] = symmetric_elements(cameras, pack_symmetric) * s;
  o.outputs["b_c"] = cameras * s;
  o.outputs["H_ll_b_l_H_lo"] = 3 * landmarks * s;
  o.outputs["H_lc"] = detail("coupling_blocks") * 6 * s;
  return o;
}

}  // namespace

const AccelerableKernel& normal_equations_kernel() {
  static const AccelerableKernel kernel{
      .name = "normal_equations",
      .mode = "slam",
      .what =
          "the window's normal equations H = Σ JᵀWJ, b = -Σ JᵀWr from the linearized "
          "reprojection, IMU and prior terms (multiplication)",
      .sizes = "m: reprojection terms; n: camera-block columns C; k: terms across keyframes",
      .host_model_degree = 1,  // linear in the terms
      .misc_add = true,        // H_cc += per-term blocks
      .derive_ops = nullptr,
      .operands = operands,
      .op_kinds = {trace::Op::Gemm, trace::Op::Syrk},
  };
  return kernel;
}

}  // namespace edx::arch
