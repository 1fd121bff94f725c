// The GPS fusion of the VIO backend (workloads/backend/vio/gps_fusion.cpp): per fused fix an EKF
// update of 3 rows, its Kalman gain and covariance update. Not one of the paper's three
// accelerated kernels; offloadable when scheduler.offload names it (issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

constexpr std::int64_t kRows = 3;  // a fix's x, y, z

/// in P n x n (sym) and per fix H 3 x n and R 3; out P n x n (sym) and the state n.
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t fixes = k.m, state = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  o.inputs["H"] = fixes * kRows * state * s;
  o.inputs["R"] = fixes * kRows * s;
  o.outputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  o.outputs["x"] = state * s;
  return o;
}

}  // namespace

const AccelerableKernel& gps_fusion_kernel() {
  static const AccelerableKernel kernel{
      .name = "gps_fusion",
      .mode = "vio",
      .what =
          "the loosely coupled GPS EKF update of each fix (the Kalman gain's and the "
          "covariance update's building blocks)",
      .sizes = "m: GPS fixes of the frame; n: state dimension",
      .host_model_degree = 1,  // per fix: linear in the fixes
      // No rule from sizes: a frame's fixes are gated one by one, and only the trace knows which
      // were fused (a GPS fusion that records no op fused none and stays on the host).
      .derive_ops = nullptr,
      .operands = operands,
      .op_kinds = {trace::Op::Gemm, trace::Op::Potrf, trace::Op::Trsm, trace::Op::Transpose},
  };
  return kernel;
}

}  // namespace edx::arch
