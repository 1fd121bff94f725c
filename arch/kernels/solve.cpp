// The solve of SLAM's Levenberg-Marquardt step (workloads/backend/slam/lm_solver.cpp): the
// reduced camera system S dx_c = s by LDLᵀ, then each landmark's inverse depth back-substituted,
// dx_l = (b_l - H_lc dx_c) / H_ll. Not one of the paper's three accelerated kernels; offloadable
// when scheduler.offload names it (issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = C camera-block columns, n = L landmarks; the couplings' count B from its gemm 1x1x6 batch.
/// In S C x C (sym), s C, H_lc (6 a block), the damped H_ll and b_l (L each); out dx_c C, dx_l L.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  std::int64_t blocks = 0;
  for (const trace::OpRecord& op : k.ops) {
    if (op.op == trace::Op::Gemm && op.m == 1 && op.n == 1 && op.k == 6) blocks += op.batch;
  }
  const std::int64_t cameras = k.m, landmarks = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["S"] = symmetric_elements(cameras, pack_symmetric) * s;
  o.inputs["s"] = cameras * s;
  o.inputs["H_lc"] = blocks * 6 * s;
  o.inputs["H_ll_b_l"] = 2 * landmarks * s;
  o.outputs["dx_c"] = cameras * s;
  o.outputs["dx_l"] = landmarks * s;
  return o;
}

}  // namespace

const AccelerableKernel& solve_kernel() {
  static const AccelerableKernel kernel{
      .name = "solve",
      .mode = "slam",
      .what =
          "the reduced camera system S dx_c = s (LDLᵀ, two triangular solves) and the "
          "landmarks' back-substitution (decomposition, substitution, multiplication)",
      .sizes = "m: camera-block columns C; n: landmarks L",
      .host_model_degree = 2,  // the LDLᵀ is cubic in C; the regression is quadratic
      .misc_add = false,
      .derive_ops = nullptr,
      .operands = operands,
      .op_kinds = {trace::Op::Ldlt, trace::Op::Trsv, trace::Op::Gemm},
  };
  return kernel;
}

}  // namespace edx::arch
