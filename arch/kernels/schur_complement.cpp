// The Schur complement of SLAM's Levenberg-Marquardt step (workloads/backend/slam/lm_solver.cpp):
// the landmarks' inverse depths eliminated from the window's normal equations. Not one of the
// paper's three accelerated kernels; offloadable when scheduler.offload names it (issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = L landmarks, n = C camera-block columns: with W = H_cl (C x L) and D = the damped H_ll
/// (diagonal L): inverse L (diagonal: reciprocals), gemm C x L x 1 (T = W D^-1, a column
/// scaling), gemm C x C x L (S = H_cc - T W^T, symmetric), gemm C x 1 x L (s = b_c - T b_l), as
/// the SLAM backend describes them (record_schur_ops: it computes them block-sparsely).
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat&) {
  namespace flags = trace::op_flags;
  using trace::Op;
  return {
      {Op::Inverse, m, m, 0, flags::kDiagonal | flags::kSymmetric, 0},  // D^-1
      {Op::Gemm, n, m, 1, 0, 0},                                        // T = W D^-1
      {Op::Gemm, n, n, m, flags::kSymmetric, 0},                        // S = H_cc - T W^T
      {Op::Gemm, n, 1, m, 0, 0},                                        // s = b_c - T b_l
  };
}

/// in H_cc C x C (sym), W C x L, D L, b_c C, b_l L; out S C x C (sym), s C.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t landmarks = k.m, cameras = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["H_cc"] = symmetric_elements(cameras, pack_symmetric) * s;
  o.inputs["H_cl"] = cameras * landmarks * s;
  o.inputs["H_ll"] = landmarks * s;  // diagonal
  o.inputs["b_c"] = cameras * s;
  o.inputs["b_l"] = landmarks * s;
  o.outputs["S"] = symmetric_elements(cameras, pack_symmetric) * s;
  o.outputs["s"] = cameras * s;
  return o;
}

}  // namespace

const AccelerableKernel& schur_complement_kernel() {
  static const AccelerableKernel kernel{
      .name = "schur_complement",
      .mode = "slam",
      .what =
          "the landmarks eliminated from the window's normal equations, S = H_cc - H_cl H_ll⁻¹ "
          "H_lc with H_ll diagonal (multiplication, inverse)",
      .sizes = "m: landmarks L; n: camera-block columns C",
      .host_model_degree = 1,  // the host's block-sparse loop is linear in the landmarks
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
