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

bool has(const OpRecord& op, std::uint32_t flag) { return (op.flags & flag) != 0; }

}  // namespace

std::int64_t symmetric_scalars(std::int64_t n, const BackendConfig& config) {
  return config.symmetric_optimization ? n * (n + 1) / 2 : n * n;
}

bool symmetric_gemm_result(const OpRecord& op) {
  return op.op == Op::Gemm && has(op, flags::kSymmetric) && op.m == op.n;
}

void check_dimensions(const OpRecord& op) {
  if (op.m < 0 || op.n < 0 || op.k < 0) {
    throw std::runtime_error(fmt::format("{} op: negative dimension (m {}, n {}, k {})",
                                         trace::to_string(op.op), op.m, op.n, op.k));
  }
  if (op.batch < 1) {
    throw std::runtime_error(
        fmt::format("{} op: batch {}, expected at least 1", trace::to_string(op.op), op.batch));
  }
}

std::int64_t factorization_macs(std::int64_t n) { return (n * n * n - n) / 6 + n * (n - 1) / 2; }

std::int64_t householder_macs(std::int64_t m, std::int64_t n) {
  std::int64_t macs = 0;
  for (std::int64_t j = 0; j < std::min(m, n); ++j) {
    const std::int64_t rows = m - j, cols = n - j - 1;
    macs += rows + 2 * rows * cols;
  }
  return macs;
}

const MatrixUnitInstance& serving_unit(trace::Op op, const BackendConfig& config) {
  if (const MatrixUnitInstance* unit = config.unit_for(op)) return *unit;
  throw std::runtime_error(
      fmt::format("no backend unit serves {} (backend.units)", trace::to_string(op)));
}

std::int64_t op_cycles(const OpRecord& op, const BackendConfig& config) {
  const MatrixUnitInstance& unit = serving_unit(op.op, config);
  return op_cycles(op, unit.count, config);
}

std::int64_t op_cycles(const OpRecord& op, int copies, const BackendConfig& config) {
  check_dimensions(op);
  const MatrixUnit& unit = *serving_unit(op.op, config).unit;
  return op.batch == 1 ? unit.cycles(op, copies, config) : unit.batch_cycles(op, copies, config);
}

OperandScalars op_operand_scalars(const OpRecord& op, const BackendConfig& config) {
  check_dimensions(op);
  if (const MatrixUnitInstance* unit = config.unit_for(op.op)) {
    if (auto own = unit->unit->own_operands(op, config)) return *own;
  }
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
      if (has(op, flags::kDiagonal)) return {m, m};
      if (has(op, flags::kSymmetric)) return {sym(m), sym(m)};
      return {m * m, m * m};
    case Op::Qr:
      return {m * n, m * n};  // in place: R above the diagonal, the reflectors below
  }
  return {};
}

std::int64_t op_spm_bytes(const OpRecord& op, const BackendConfig& config) {
  const OperandScalars operands = op_operand_scalars(op, config);
  // Factorizations overwrite their matrix and triangular solves their right-hand side: an
  // in-place op holds its inputs only; the others hold inputs and result.
  const bool in_place = op.op == Op::Potrf || op.op == Op::Ldlt || op.op == Op::Trsm ||
                        op.op == Op::Trsv || op.op == Op::Qr;
  return (in_place ? operands.in : operands.in + operands.out) * config.scalar_bytes();
}

namespace {

/// Multiply-adds of one instance of `op` (op_macs without the batch).
std::int64_t instance_macs(const OpRecord& op, const BackendConfig& config) {
  if (const MatrixUnitInstance* unit = config.unit_for(op.op)) {
    if (auto own = unit->unit->own_macs(op, config)) return *own;
  }
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
      return has(op, flags::kDiagonal) ? 0 : m * m * m;
    case Op::Qr:
      return householder_macs(m, n);
  }
  return 0;
}

}  // namespace

std::int64_t op_macs(const OpRecord& op, const BackendConfig& config) {
  check_dimensions(op);
  return op.batch * instance_macs(op, config);
}

std::int64_t spill_tile(const BackendConfig& config) {
  const std::int64_t scalars = config.spm_bytes / config.scalar_bytes();
  // ⌊√(M/3)⌋ in integers: the largest t with 3t² <= M.
  auto t = static_cast<std::int64_t>(std::sqrt(static_cast<double>(scalars) / 3.0));
  while (t > 0 && 3 * t * t > scalars) --t;
  while (3 * (t + 1) * (t + 1) <= scalars) ++t;
  return std::max<std::int64_t>(1, t);
}

SpillTraffic op_spill_traffic(const OpRecord& op, const BackendConfig& config) {
  if (op_spm_bytes(op, config) <= config.spm_bytes) return {};
  const OperandScalars io = op_operand_scalars(op, config);
  const std::int64_t rereads = ceil_div(2 * instance_macs(op, config), spill_tile(config));
  return {op.batch * std::max(io.in, rereads) * config.scalar_bytes(),
          op.batch * io.out * config.scalar_bytes()};
}

std::vector<OpRecord> kernel_ops(const trace::KernelRecord& kernel, const BackendConfig& config) {
  if (!kernel.ops.empty()) return kernel.ops;
  if (kernel.m < 0 || kernel.n < 0) {
    throw std::runtime_error(
        fmt::format("kernel '{}': negative size (m {}, n {})", kernel.kernel, kernel.m, kernel.n));
  }
  const AccelerableKernel* descriptor = find_accelerable_kernel(kernel.kernel);
  if (descriptor == nullptr || descriptor->derive_ops == nullptr) {
    throw std::runtime_error(
        fmt::format("kernel '{}': no ops recorded and no rule to derive them (expected {}, or a "
                    "trace with ops)",
                    kernel.kernel, accelerable_kernel_names()));
  }
  return descriptor->derive_ops(kernel.m, kernel.n, config.matrix_format());
}

bool has_ops(const trace::KernelRecord& kernel) {
  if (!kernel.ops.empty()) return true;
  const AccelerableKernel* descriptor = find_accelerable_kernel(kernel.kernel);
  return descriptor != nullptr && descriptor->derive_ops != nullptr;
}

bool offloadable(const trace::KernelRecord& kernel, const BackendConfig& config) {
  for (const OpRecord& op : kernel_ops(kernel, config)) {
    if (config.unit_for(op.op) == nullptr) return false;
  }
  return true;
}

std::vector<std::string> kernels_using(std::size_t unit, const BackendConfig& config,
                                       const std::vector<std::string>& offload) {
  // Sizes large enough that every kernel derives its full op list (r > 0 for marginalization).
  const KernelMatrixFormat format{8, kPoseBlock, 3};
  std::vector<std::string> out;
  for (const AccelerableKernel* k : accelerable_kernels()) {
    if (std::find(offload.begin(), offload.end(), k->name) == offload.end()) continue;
    std::vector<trace::Op> kinds = k->op_kinds;
    if (k->derive_ops != nullptr) {
      for (const OpRecord& op : k->derive_ops(8, 8, format)) kinds.push_back(op.op);
    }
    if (std::any_of(kinds.begin(), kinds.end(),
                    [&](trace::Op op) { return config.unit_for(op) == &config.units[unit]; })) {
      out.emplace_back(k->name);
    }
  }
  return out;
}

std::int64_t kernel_cycles(const trace::KernelRecord& kernel, const BackendConfig& config) {
  std::int64_t cycles = 0;
  for (const OpRecord& op : kernel_ops(kernel, config)) cycles += op_cycles(op, config);
  return cycles;
}

}  // namespace edx::arch
