#include "arch/backend/op_timing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edx::arch {
namespace {

namespace flags = trace::op_flags;
using trace::Op;
using trace::OpRecord;

/// Scalars of an n x n symmetric matrix as stored: n(n+1)/2 with the optimization, else n^2.
std::int64_t symmetric_scalars(std::int64_t n, const BackendConfig& config) {
  return config.symmetric_optimization ? n * (n + 1) / 2 : n * n;
}

bool has(const OpRecord& op, std::uint32_t flag) { return (op.flags & flag) != 0; }

/// A gemm whose (square) result is symmetric (see op_timing.hpp).
bool symmetric_gemm_result(const OpRecord& op) {
  return op.op == Op::Gemm && has(op, flags::kSymmetric) && op.m == op.n;
}

void check_dimensions(const OpRecord& op) {
  if (op.m < 0 || op.n < 0 || op.k < 0) {
    throw std::runtime_error(fmt::format("{} op: negative dimension (m {}, n {}, k {})",
                                         trace::to_string(op.op), op.m, op.n, op.k));
  }
}

}  // namespace

std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

std::int64_t gemm_tiles(std::int64_t m, std::int64_t n, int block, bool symmetric_result) {
  const std::int64_t rows = ceil_div(m, block);
  if (symmetric_result) return rows * (rows + 1) / 2;  // tiles on and above the diagonal
  return rows * ceil_div(n, block);
}

std::int64_t factorization_macs(std::int64_t n) { return (n * n * n - n) / 6 + n * (n - 1) / 2; }

std::int64_t general_inverse_cycles(std::int64_t n, const BackendConfig& config) {
  return n * config.divide_latency_cycles + ceil_div(n * n * n, config.inverse_lanes);
}

std::int64_t structured_inverse_cycles(std::int64_t m, const BackendConfig& config) {
  const std::int64_t d = m - kPoseBlock;  // diagonal (landmark) part
  const std::int64_t lanes = config.inverse_lanes;
  const std::int64_t reciprocals = config.divide_latency_cycles + ceil_div(d, lanes);
  const std::int64_t pose_inverse = general_inverse_cycles(kPoseBlock, config);
  // A^-1 B (6d) + B^T A^-1 B (36d) + A^-1 B S^-1 (36d) + the top-left block (6 per entry).
  const std::int64_t products = 78 * d + kPoseBlock * symmetric_scalars(d, config);
  return reciprocals + pose_inverse + ceil_div(products, lanes);
}

std::int64_t array_cycles(std::int64_t tiles, std::int64_t k, const BackendConfig& config) {
  if (tiles == 0 || k == 0) return 0;
  const std::int64_t b = config.gemm_block;
  if (config.gemm_overlap_tiles) return tiles * std::max(k, b) + 2 * b;
  return tiles * (k + 2 * b);
}

std::int64_t blocked_substitution_cycles(std::int64_t m, std::int64_t rhs,
                                         const BackendConfig& config) {
  if (m == 0 || rhs == 0) return 0;
  const std::int64_t b = config.gemm_block;
  std::int64_t cycles = config.divide_latency_cycles + (m - 1);  // all reciprocals, pipelined
  for (std::int64_t done = 0; done < m; done += b) {
    const std::int64_t s = std::min(b, m - done);
    // B_i -= L_i,<i X_<i on the array (s x rhs result, k = done), then the s x s solve.
    if (done > 0) {
      cycles += array_cycles(gemm_tiles(s, rhs, config.gemm_block, false), done, config);
    }
    cycles += s + ceil_div(rhs * s * (s + 1) / 2, config.trsv_lanes);
  }
  return cycles;
}

std::int64_t blocked_factorization_cycles(std::int64_t m, std::int64_t per_column,
                                          const BackendConfig& config) {
  const std::int64_t b = config.gemm_block;
  std::int64_t cycles = 0;
  for (std::int64_t done = 0; done < m; done += b) {
    const std::int64_t s = std::min(b, m - done);
    const std::int64_t rest = m - done - s;
    // The diagonal block on the decomposition unit.
    cycles += ceil_div(factorization_macs(s), config.decomp_lanes()) + s * per_column;
    if (rest == 0) break;
    // The panel below it on the substitution unit (reciprocals known from the diagonal block),
    // then the trailing update A_22 -= L_21 L_21^T on the array (a syrk, k = s).
    cycles += s + ceil_div(rest * s * (s + 1) / 2, config.trsv_lanes);
    cycles += array_cycles(gemm_tiles(rest, rest, config.gemm_block, config.symmetric_optimization),
                           s, config);
  }
  return cycles;
}

bool uses_structured_inverse(const OpRecord& op, const BackendConfig& config) {
  return config.structured_inverse && op.op == Op::Inverse && has(op, flags::kDiagonalBlock) &&
         has(op, flags::kBlock6x6) && op.m > kPoseBlock;
}

std::int64_t op_cycles(const OpRecord& op, const BackendConfig& config) {
  check_dimensions(op);
  const std::int64_t m = op.m, n = op.n, k = op.k;
  const std::int64_t t_div = config.divide_latency_cycles;
  switch (op.op) {
    case Op::Gemm: {
      if (m == 0 || n == 0 || k == 0) return 0;
      const bool symmetric = config.symmetric_optimization && symmetric_gemm_result(op);
      return array_cycles(gemm_tiles(m, n, config.gemm_block, symmetric), k, config);
    }
    case Op::Syrk:
      if (m == 0 || k == 0) return 0;
      return array_cycles(gemm_tiles(m, m, config.gemm_block, config.symmetric_optimization), k,
                          config);
    case Op::Potrf:
    case Op::Ldlt: {
      if (m == 0) return 0;
      const std::int64_t per_column =
          op.op == Op::Potrf ? config.sqrt_latency_cycles + t_div : t_div;
      if (config.blocked_solvers) return blocked_factorization_cycles(m, per_column, config);
      return ceil_div(factorization_macs(m), config.decomp_lanes()) + m * per_column;
    }
    case Op::Trsm:
    case Op::Trsv: {
      const std::int64_t rhs = op.op == Op::Trsv ? 1 : n;
      if (m == 0 || rhs == 0) return 0;
      if (config.blocked_solvers) return blocked_substitution_cycles(m, rhs, config);
      return t_div + (m - 1) + m + ceil_div(rhs * m * (m + 1) / 2, config.trsv_lanes);
    }
    case Op::Transpose:
      return ceil_div(m * n, config.transpose_words_per_cycle);
    case Op::Inverse:
      if (m == 0) return 0;
      return uses_structured_inverse(op, config) ? structured_inverse_cycles(m, config)
                                                 : general_inverse_cycles(m, config);
  }
  return 0;
}

std::int64_t op_spm_bytes(const OpRecord& op, const BackendConfig& config) {
  const OperandScalars operands = op_operand_scalars(op, config);
  // Factorizations overwrite their matrix and triangular solves their right-hand side: an
  // in-place op holds its inputs only; the others hold inputs and result.
  const bool in_place =
      op.op == Op::Potrf || op.op == Op::Ldlt || op.op == Op::Trsm || op.op == Op::Trsv;
  return (in_place ? operands.in : operands.in + operands.out) * config.scalar_bytes;
}

OperandScalars op_operand_scalars(const OpRecord& op, const BackendConfig& config) {
  check_dimensions(op);
  const std::int64_t m = op.m, n = op.n, k = op.k;
  const auto sym = [&](std::int64_t s) { return symmetric_scalars(s, config); };
  switch (op.op) {
    case Op::Gemm: {
      std::int64_t a = m * k, b = k * n, c = m * n;
      if (has(op, flags::kSymmetric)) {
        if (m == n) {
          c = sym(m);
        } else if (m == k) {
          a = sym(m);
        } else if (k == n) {
          b = sym(k);
        }
      }
      return {a + b, c};
    }
    case Op::Syrk:
      return {m * k, sym(m)};
    case Op::Potrf:
    case Op::Ldlt:
      return {sym(m), sym(m)};
    case Op::Trsm:
    case Op::Trsv: {
      const std::int64_t rhs = m * (op.op == Op::Trsv ? 1 : n);
      return {sym(m) + rhs, rhs};
    }
    case Op::Transpose:
      return {m * n, m * n};
    case Op::Inverse:
      if (uses_structured_inverse(op, config)) {
        const std::int64_t d = m - kPoseBlock;
        return {d + d * kPoseBlock + sym(kPoseBlock), sym(m)};
      }
      if (has(op, flags::kSymmetric)) return {sym(m), sym(m)};
      return {m * m, m * m};
  }
  return {};
}

std::int64_t op_macs(const OpRecord& op, const BackendConfig& config) {
  check_dimensions(op);
  const std::int64_t m = op.m, n = op.n, k = op.k;
  switch (op.op) {
    case Op::Gemm:
      if (config.symmetric_optimization && symmetric_gemm_result(op)) {
        return k * symmetric_scalars(m, config);
      }
      return m * n * k;
    case Op::Syrk:
      return k * symmetric_scalars(m, config);
    case Op::Potrf:
    case Op::Ldlt:
      return factorization_macs(m);
    case Op::Trsm:
    case Op::Trsv:
      return (op.op == Op::Trsv ? 1 : n) * m * (m + 1) / 2;
    case Op::Transpose:
      return 0;
    case Op::Inverse:
      if (m == 0) return 0;
      if (uses_structured_inverse(op, config)) {
        const std::int64_t d = m - kPoseBlock;
        return 78 * d + kPoseBlock * symmetric_scalars(d, config);
      }
      return m * m * m;
  }
  return 0;
}

std::int64_t spill_tile(const BackendConfig& config) {
  const std::int64_t scalars = config.spm_bytes / config.scalar_bytes;
  // ⌊√(M/3)⌋ in integers: the largest t with 3t² <= M.
  auto t = static_cast<std::int64_t>(std::sqrt(static_cast<double>(scalars) / 3.0));
  while (t > 0 && 3 * t * t > scalars) --t;
  while (3 * (t + 1) * (t + 1) <= scalars) ++t;
  return std::max<std::int64_t>(1, t);
}

SpillTraffic op_spill_traffic(const OpRecord& op, const BackendConfig& config) {
  if (op_spm_bytes(op, config) <= config.spm_bytes) return {};
  const OperandScalars io = op_operand_scalars(op, config);
  const std::int64_t rereads = ceil_div(2 * op_macs(op, config), spill_tile(config));
  return {std::max(io.in, rereads) * config.scalar_bytes, io.out * config.scalar_bytes};
}

std::vector<OpRecord> kernel_ops(const trace::KernelRecord& kernel, const BackendConfig& config) {
  if (!kernel.ops.empty()) return kernel.ops;
  if (kernel.m < 0 || kernel.n < 0) {
    throw std::runtime_error(
        fmt::format("kernel '{}': negative size (m {}, n {})", kernel.kernel, kernel.m, kernel.n));
  }
  const AccelerableKernel* descriptor = find_accelerable_kernel(kernel.kernel);
  if (descriptor == nullptr) {
    throw std::runtime_error(
        fmt::format("kernel '{}': no ops recorded and no rule to derive them (expected {}, or a "
                    "trace with ops)",
                    kernel.kernel, accelerable_kernel_names()));
  }
  return descriptor->derive_ops(kernel.m, kernel.n, config.matrix_format());
}

std::int64_t kernel_cycles(const trace::KernelRecord& kernel, const BackendConfig& config) {
  std::int64_t cycles = 0;
  for (const OpRecord& op : kernel_ops(kernel, config)) cycles += op_cycles(op, config);
  return cycles;
}

double kernel_seconds(const trace::KernelRecord& kernel, const BackendConfig& config) {
  return static_cast<double>(kernel_cycles(kernel, config)) / (config.clock_mhz * 1e6);
}

double predict_kernel_seconds(const std::string& kernel, std::int64_t m, std::int64_t n,
                              const BackendConfig& config) {
  trace::KernelRecord record;
  record.kernel = kernel;
  record.accelerable = true;
  record.m = m;
  record.n = n;
  return kernel_seconds(record, config);
}

}  // namespace edx::arch
