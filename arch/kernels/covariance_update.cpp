// The covariance update of the MSCKF (workloads/backend/vio/ekf_update.cpp update_covariance):
// P <- P - K (P H^T)^T, kept symmetric. Not one of the paper's three accelerated kernels;
// offloadable when scheduler.offload names it (issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = rows of H, n = state: gemm n x n x m (P - K (P H^T)^T, a symmetric result; B transposed),
/// transpose n x n (the symmetrization (P + P^T) / 2).
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat&) {
  namespace flags = trace::op_flags;
  using trace::Op;
  return {
      {Op::Gemm, n, n, m, flags::kSymmetric | flags::kTransposeB, 0},
      {Op::Transpose, n, n, 0, 0, 0},
  };
}

/// in P n x n (sym), K n x m, P H^T n x m; out P n x n (sym).
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t rows = k.m, state = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  o.inputs["K"] = state * rows * s;
  o.inputs["PHt"] = state * rows * s;
  o.outputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  return o;
}

}  // namespace

const AccelerableKernel& covariance_update_kernel() {
  static const AccelerableKernel kernel{
      .name = "covariance_update",
      .mode = "vio",
      .what = "the MSCKF's P <- P - K (P Hᵀ)ᵀ, kept symmetric (multiplication, transpose)",
      .sizes = "m: rows of H; n: state dimension",
      .host_model_degree = 1,  // n² m: linear in the rows at a given state
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
