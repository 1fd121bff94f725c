// The MSCKF's covariance propagation over a frame's IMU interval
// (workloads/backend/vio/imu_propagator.cpp propagate_covariance): Φ = Π Φ_k and Q accumulated
// over the m sample intervals, then P_II <- Φ P_II Φᵀ + Q, P_IR <- Φ P_IR. The mean's integration
// stays on the host (kernel "imu_propagation"). Not one of the paper's three accelerated kernels;
// offloadable when scheduler.offload names it (issue 40).
#include "arch/kernels/kernels.hpp"

namespace edx::arch {
namespace {

constexpr std::int64_t kImu = 15;  ///< the IMU block of the MSCKF state

/// m = sample intervals, n = state: per interval gemm 15x15x15 twice (Φ Φ_total, Φ Q_total) and
/// once with a symmetric result (… Φᵀ); then gemm 15x15x15 (Φ P_II), its symmetric (… Φᵀ), gemm
/// 15 x (n - 15) x 15 (Φ P_IR), transpose 15 x (n - 15) and the symmetrization, transpose n x n
/// (as the VIO backend describes them).
std::vector<trace::OpRecord> ops(std::int64_t m, std::int64_t n, const KernelMatrixFormat&) {
  namespace flags = trace::op_flags;
  using trace::Op;
  const std::uint32_t symmetric_result = flags::kSymmetric | flags::kTransposeB;
  std::vector<trace::OpRecord> out;
  if (m > 0) {
    out.push_back({Op::Gemm, kImu, kImu, kImu, 0, 0, 2 * m});
    out.push_back({Op::Gemm, kImu, kImu, kImu, symmetric_result, 0, m});
  }
  out.push_back({Op::Gemm, kImu, kImu, kImu, 0, 0});
  out.push_back({Op::Gemm, kImu, kImu, kImu, symmetric_result, 0});
  if (n > kImu) {
    out.push_back({Op::Gemm, kImu, n - kImu, kImu, 0, 0});
    out.push_back({Op::Transpose, kImu, n - kImu, 0, 0, 0});
  }
  out.push_back({Op::Transpose, n, n, 0, 0, 0});
  return out;
}

/// in P n x n (sym), per interval Φ_k 15 x 15 and Q_k (sym); out P n x n (sym).
KernelOperands operands(const trace::KernelRecord& k, const KernelMatrixFormat& f,
                        bool pack_symmetric) {
  const std::int64_t steps = k.m, state = k.n, s = f.scalar_bytes;
  KernelOperands o;
  o.inputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  o.inputs["Phi"] = steps * kImu * kImu * s;
  o.inputs["Q"] = steps * symmetric_elements(kImu, pack_symmetric) * s;
  o.outputs["P"] = symmetric_elements(state, pack_symmetric) * s;
  return o;
}

}  // namespace

const AccelerableKernel& covariance_propagation_kernel() {
  static const AccelerableKernel kernel{
      .name = "covariance_propagation",
      .mode = "vio",
      .what =
          "the MSCKF's covariance over a frame's IMU interval, P_II <- Φ P_II Φᵀ + Q, "
          "P_IR <- Φ P_IR (multiplication, transpose)",
      .sizes = "m: IMU sample intervals; n: state dimension",
      .host_model_degree = 1,  // linear in the intervals at a given state
      .derive_ops = ops,
      .operands = operands,
  };
  return kernel;
}

}  // namespace edx::arch
