// Marginalization of the oldest keyframe's landmarks in the sliding window (SLAM, paper
// Sec. VI-A): the Schur complement with the structured inverse of A_mm = [A B; Bᵀ D].
#include <fmt/format.h>

#include <stdexcept>

#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m landmarks, n = r kept states; mm = m l + p. Inverse mm (diagonal block, symmetric, 6x6 block
/// when p = 6), transpose mm x r, gemm (r, mm, mm), gemm (r, r, mm; symmetric), gemm (r, 1, mm),
/// ldlt r, trsv r, transpose r x r (workloads/backend/slam/marginalizer.cpp); with r = 0 only
/// the inverse.
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat& f) {
  namespace flags = trace::op_flags;
  using trace::Op;
  const std::int64_t mm = m * f.landmark_dim + f.pose_dim;
  const std::int64_t r = n;
  std::vector<trace::OpRecord> out = {{Op::Inverse, mm, mm, 0,
                                       flags::kDiagonalBlock | flags::kSymmetric |
                                           (f.pose_dim == kPoseBlock ? flags::kBlock6x6 : 0u),
                                       0}};
  if (r > 0) {
    out.insert(out.end(), {
                              {Op::Transpose, mm, r, 0, 0, 0},              // A_rm = A_mrᵀ
                              {Op::Gemm, r, mm, mm, flags::kSymmetric, 0},  // T = A_rm A_mm⁻¹
                              {Op::Gemm, r, r, mm, flags::kSymmetric, 0},   // H* = A_rr − T A_mr
                              {Op::Gemm, r, 1, mm, 0, 0},                   // b* = b_r − T b_m
                              {Op::Ldlt, r, r, 0, flags::kSymmetric, 0},    // H* = Pᵀ L D Lᵀ P
                              {Op::Trsv, r, 1, 0, flags::kLower, 0},        // L⁻¹ P b*
                              {Op::Transpose, r, r, 0, flags::kLower, 0},   // J = D^½ Lᵀ P
                          });
  }
  return out;
}

/// Parameters per landmark l: the kernel's detail "landmark_dim" if given, else (inverse op size
/// − p) / m when the kernel records the A_mm inverse, else the configured backend.landmark_dim.
std::int64_t landmark_dim(const trace::KernelRecord& k, const KernelMatrixFormat& f) {
  if (const auto l = detail_integer(k, "landmark_dim", 1)) return *l;
  if (k.m > 0) {
    for (const trace::OpRecord& op : k.ops) {
      const std::int64_t landmark_part = op.m - f.pose_dim;
      if (op.op == trace::Op::Inverse && landmark_part > 0 && landmark_part % k.m == 0) {
        return landmark_part / k.m;  // A_mm inverse: d_m = m l + p
      }
    }
  }
  return f.landmark_dim;
}

/// m landmarks, n kept; d_l = m l, d_m = d_l + p. in: A_mm as its blocks [A B; Bᵀ D] (A
/// block-diagonal m l², B d_l x p, D p x p sym), A_mr d_m x n, A_rr n x n (sym), b_m d_m, b_r n;
/// out: the prior A_rr − A_rm A_mm⁻¹ A_mr n x n (sym) and its b, n.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t landmarks = k.m, kept = k.n, s = f.scalar_bytes;
  const std::int64_t l = landmark_dim(k, f);
  const std::int64_t p = f.pose_dim;
  const std::int64_t dl = landmarks * l;  // d_l
  const std::int64_t dm = dl + p;         // d_m
  KernelOperands o;
  o.inputs["A_mm.A"] = landmarks * l * l * s;                       // m blocks l x l
  o.inputs["A_mm.B"] = dl * p * s;                                  // d_l x p
  o.inputs["A_mm.D"] = symmetric_elements(p, pack_symmetric) * s;   // p x p
  o.inputs["A_mr"] = dm * kept * s;                                 // d_m x n
  o.inputs["A_rr"] = symmetric_elements(kept, pack_symmetric) * s;  // n x n
  o.inputs["b_m"] = dm * s;
  o.inputs["b_r"] = kept * s;
  o.outputs["prior_H"] = symmetric_elements(kept, pack_symmetric) * s;  // Schur complement
  o.outputs["prior_b"] = kept * s;
  return o;
}

}  // namespace

const AccelerableKernel& marginalization_kernel() {
  static const AccelerableKernel kernel{
      .name = "marginalization",
      .mode = "slam",
      .what =
          "the prior of the sliding window, A_rr − A_rm A_mm⁻¹ A_mr with A_mm = [A B; Bᵀ D], "
          "A diagonal, D 6x6 (Sec. VI-A, Table II: all five building blocks)",
      .sizes = "m: landmarks marginalized; n: kept state dimension r",
      .host_model_degree = 2,
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
