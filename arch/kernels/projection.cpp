// Projection of the map's points into the camera (registration, paper Sec. VI-A).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

/// C (3x4) · X (4xM): one gemm m=3, n=M, k=4.
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t, const KernelMatrixFormat&) {
  return {trace::OpRecord{trace::Op::Gemm, 3, m, 4, 0, 0}};
}

/// in C 3x4 + X 4xM = (12 + 4M) s; out 2xM image points = 2M s.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f, bool) {
  const std::int64_t points = k.m, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["camera_matrix"] = 12 * s;          // C 3x4
  o.inputs["points"] = 4 * points * s;         // X 4xM homogeneous
  o.outputs["image_points"] = 2 * points * s;  // 2xM
  return o;
}

}  // namespace

const AccelerableKernel& projection_kernel() {
  static const AccelerableKernel kernel{
      .name = "projection",
      .mode = "registration",
      .what =
          "projects the map's 3D points into the image, C·X (Sec. VI-A, Table II: matrix "
          "multiplication)",
      .sizes = "m: map points M",
      .host_model_degree = 1,  // M·12 multiply-adds: linear in M
      .misc_add = false,       // C X alone
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
