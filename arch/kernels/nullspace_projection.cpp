// The MSCKF's null-space projection (workloads/backend/vio/msckf_updater.cpp project_out_points):
// each feature's point projected out of its rows by a Householder QR of H_f, Qᵀ applied to H_x
// and r, and the chi-square gate on the projected rows. Not one of the paper's three accelerated
// kernels; offloadable when scheduler.offload names it and a unit serves qr (householder, issue
// 40). Its ops are per feature, by shape: only the trace knows them (no derive_ops).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = accepted rows, n = state, the ops' qr batches the features: in H_x R x n, H_f R x 3 and
/// r R (R = Σ rows of the projected features, from the qr ops), P n x n (sym) for the gate; out
/// the accepted rows H n wide and r, m x (n + 1).
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  std::int64_t rows_in = 0;
  for (const trace::OpRecord& op : k.ops) {
    if (op.op == trace::Op::Qr) rows_in += op.m * op.batch;
  }
  const std::int64_t state = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["H_x"] = rows_in * state * s;
  o.inputs["H_f"] = rows_in * 3 * s;
  o.inputs["r"] = rows_in * s;
  o.inputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  o.outputs["H"] = k.m * state * s;
  o.outputs["r"] = k.m * s;
  return o;
}

}  // namespace

const AccelerableKernel& nullspace_projection_kernel() {
  static const AccelerableKernel kernel{
      .name = "nullspace_projection",
      .mode = "vio",
      .what =
          "each feature's point projected out of its rows (Householder QR of H_f, Qᵀ applied "
          "to H_x and r) and its chi-square gate (QR, multiplication, decomposition, "
          "substitution)",
      .sizes = "m: accepted rows; n: state dimension",
      .host_model_degree = 1,  // per feature: linear in the rows at a given state
      .misc_add = false,
      .derive_ops = nullptr,
      .operands = operands,
      .op_kinds = {trace::Op::Qr, trace::Op::Gemm, trace::Op::Ldlt, trace::Op::Trsv},
  };
  return kernel;
}

}  // namespace edx::arch
