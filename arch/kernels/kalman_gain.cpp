// The Kalman gain of the MSCKF update (VIO, paper Sec. VI-A).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = rows of H, n = state: gemm P Hᵀ (n, m, n; symmetric P, B transposed), gemm S = H (P Hᵀ)
/// (m, m, n; symmetric), potrf m, trsm m x n lower, trsm m x n upper, transpose m x n
/// (workloads/backend/vio/ekf_update.cpp).
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat&) {
  namespace flags = trace::op_flags;
  using trace::Op;
  return {
      {Op::Gemm, n, m, n, flags::kSymmetric | flags::kTransposeB, 0},  // P Hᵀ
      {Op::Gemm, m, m, n, flags::kSymmetric, 0},                       // S = H (P Hᵀ)
      {Op::Potrf, m, m, 0, flags::kSymmetric, 0},                      // S = L Lᵀ
      {Op::Trsm, m, n, 0, flags::kLower, 0},                           // L Y = H P
      {Op::Trsm, m, n, 0, flags::kUpper, 0},                           // Lᵀ Kᵀ = Y
      {Op::Transpose, m, n, 0, 0, 0},                                  // K
  };
}

/// in H mxn + P nxn (sym) + R diagonal m = (mn + sym(n) + m) s; out K nxm = nm s.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t rows = k.m, state = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["H"] = rows * state * s;                               // m x n
  o.inputs["P"] = symmetric_elements(state, pack_symmetric) * s;  // n x n covariance
  o.inputs["R"] = rows * s;                                       // diagonal m x m
  o.outputs["K"] = state * rows * s;                              // n x m
  return o;
}

}  // namespace

const AccelerableKernel& kalman_gain_kernel() {
  static const AccelerableKernel kernel{
      .name = "kalman_gain",
      .mode = "vio",
      .what =
          "the MSCKF update's gain K = P Hᵀ (H P Hᵀ + R)⁻¹ (Sec. VI-A, Table II: "
          "multiplication, decomposition, substitution, transpose)",
      .sizes = "m: rows of H; n: state dimension",
      .host_model_degree = 2,
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
