// The MSCKF's measurement compression (workloads/backend/vio/msckf_updater.cpp compress, an option
// off by default): the stacked rows' thin QR on the state columns they touch, H <- T (c x c upper)
// and r <- Q1ᵀ r. Not one of the paper's three accelerated kernels; offloadable when
// scheduler.offload names it and a unit serves qr (householder, issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// m = stacked rows, n = c touched columns. In H m x c, r m; out T c x c (upper), r c.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f, bool) {
  const std::int64_t rows = k.m, cols = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["H"] = rows * cols * s;
  o.inputs["r"] = rows * s;
  o.outputs["T"] = cols * (cols + 1) / 2 * s;
  o.outputs["r"] = cols * s;
  return o;
}

/// qr m x n, then Q1ᵀ r in the WY form: gemm n x 1 x m, n x 1 x n, m x 1 x n (as recorded).
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat&) {
  namespace flags = trace::op_flags;
  using trace::Op;
  return {
      {Op::Qr, m, n, 0, 0, 0},
      {Op::Gemm, n, 1, m, flags::kTransposeA, 0},
      {Op::Gemm, n, 1, n, flags::kUpper | flags::kTransposeA, 0},
      {Op::Gemm, m, 1, n, 0, 0},
  };
}

}  // namespace

const AccelerableKernel& compression_kernel() {
  static const AccelerableKernel kernel{
      .name = "compression",
      .mode = "vio",
      .what =
          "the stacked rows' thin QR on the columns they touch, H <- T, r <- Q1ᵀ r (QR, "
          "multiplication)",
      .sizes = "m: stacked rows; n: state columns touched",
      .host_model_degree = 1,  // m n²: linear in the rows at a given width
      .misc_add = false,
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
