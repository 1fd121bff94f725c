#include "arch/backend/units.hpp"

#include <algorithm>

#include "arch/kernels/kernels.hpp"

namespace edx::arch {

const std::array<BackendUnitDescriptor, kBackendUnitCount>& backend_units() {
  using trace::Op;
  static const std::array<BackendUnitDescriptor, kBackendUnitCount> units = {{
      {BackendUnit::kMultiply,
       "multiply",
       "gemm",
       "matrix multiplication (b x b array)",
       {Op::Gemm, Op::Syrk},
       [](const BackendConfig& c) { return double(c.gemm_block) * c.gemm_block; }},
      {BackendUnit::kDecompose,
       "decompose",
       "decomposition",
       "Cholesky / LDLᵀ decomposition",
       {Op::Potrf, Op::Ldlt},
       [](const BackendConfig& c) { return double(c.decomp_lanes()); }},
      {BackendUnit::kInverse,
       "inverse",
       "inverse",
       "inverse (diagonal + 6x6 structured)",
       {Op::Inverse},
       [](const BackendConfig& c) { return double(c.inverse_lanes); }},
      {BackendUnit::kTranspose,
       "transpose",
       "transpose",
       "transpose (moves words, no arithmetic)",
       {Op::Transpose},
       [](const BackendConfig&) { return 0.0; }},
      {BackendUnit::kSubstitute,
       "substitute",
       "substitution",
       "forward / back substitution",
       {Op::Trsm, Op::Trsv},
       [](const BackendConfig& c) { return double(c.trsv_lanes); }},
  }};
  return units;
}

const BackendUnitDescriptor& backend_unit(BackendUnit unit) {
  return backend_units()[static_cast<std::size_t>(unit)];
}

const char* to_string(BackendUnit unit) { return backend_unit(unit).name.data(); }

BackendUnit unit_of(trace::Op op) {
  for (const BackendUnitDescriptor& u : backend_units()) {
    if (std::find(u.ops.begin(), u.ops.end(), op) != u.ops.end()) return u.unit;
  }
  return BackendUnit::kMultiply;  // every trace::Op is served above (a test checks)
}

std::vector<std::string> kernels_using(BackendUnit unit) {
  // Sizes large enough that every kernel derives its full op list (r > 0 for marginalization).
  const KernelMatrixFormat format{8, kPoseBlock, 3};
  std::vector<std::string> out;
  for (const AccelerableKernel* k : accelerable_kernels()) {
    const auto ops = k->derive_ops(8, 8, format);
    if (std::any_of(ops.begin(), ops.end(),
                    [&](const trace::OpRecord& op) { return unit_of(op.op) == unit; })) {
      out.emplace_back(k->name);
    }
  }
  return out;
}

}  // namespace edx::arch
