#include "arch/backend/accelerators/fpga_matrix_units.hpp"

#include <algorithm>

#include "arch/backend/backend_accelerator.hpp"
#include "arch/backend/kernel_replay.hpp"
#include "arch/backend/op_timing.hpp"

namespace edx::arch {
namespace {

/// "Misc." of Fig. 14: one adder at the backend's precision (e.g. + R in S = H P H^T + R).
cost::Resources misc_cost(const BackendConfig& be) {
  cost::Datapath d;
  d.fp(1, be.precision == trace::Precision::kFp32 ? cost::kSingleAdd : cost::kDoubleAdd);
  return d.resources();
}

}  // namespace

FpgaMatrixUnits::FpgaMatrixUnits(const BackendConfig& config) : config_(config) {
  config_.validate();
}

std::vector<std::string> FpgaMatrixUnits::resource_names() const {
  std::vector<std::string> names;
  for (const MatrixUnitInstance& u : config_.units) {
    if (u.count > 0) names.push_back(u.name);
  }
  return names;
}

std::unique_ptr<const OffloadPlan> FpgaMatrixUnits::plan(const trace::KernelRecord& kernel) const {
  return std::make_unique<const KernelAccelResult>(accelerate_kernel(kernel, config_));
}

std::unique_ptr<OffloadPlanner> FpgaMatrixUnits::planner() const {
  struct Planner final : OffloadPlanner {
    explicit Planner(const BackendConfig& c) : config(c) {}
    std::unique_ptr<const OffloadPlan> plan(const trace::KernelRecord& kernel) override {
      return std::make_unique<const KernelAccelResult>(accelerate_kernel(kernel, config, memo));
    }
    const BackendConfig& config;
    OpTimingMemo memo;
  };
  return std::make_unique<Planner>(config_);
}

std::unique_ptr<OffloadModel> FpgaMatrixUnits::instantiate(sim::Simulator& sim) const {
  return std::make_unique<BackendAccelerator>(sim, config_);
}

std::vector<cost::CostEntry> FpgaMatrixUnits::cost_entries(
    const AcceleratorCostContext& context) const {
  const auto kernels = [&](double n) { return context.ns_per_kernel ? n : 1.0; };
  std::vector<cost::CostEntry> v;
  // Table II: the non-shared design has one copy of a building block per kernel that uses it
  // (from the kernels' ops: multiply 3, decompose 2, inverse 1, transpose 2, substitute 2).
  for (std::size_t i = 0; i < config_.units.size(); ++i) {
    const MatrixUnitInstance& u = config_.units[i];
    if (u.count == 0) continue;
    v.push_back(cost::CostEntry::replicated(
        u.name, "backend", "unit", u.unit->resources(u.arithmetic()) * u.count,
        kernels(double(kernels_using(i, config_, context.offload).size()))));
  }
  // The adder of "Misc." per kernel that adds (the paper's: Kalman gain's + R, marginalization),
  // the operand SPM per kernel.
  double adders = 0;
  for (const std::string& name : context.offload) {
    adders += accelerable_kernel(name).misc_add ? 1 : 0;
  }
  v.push_back(
      cost::CostEntry::replicated("misc", "backend", "unit", misc_cost(config_), kernels(adders)));
  for (const MemoryStructure& s : backend_memories(config_)) {
    s.validate();
    v.push_back(cost::CostEntry::replicated(s.name, "backend", "memory", context.memory_cost(s),
                                            kernels(double(context.offload.size()))));
  }
  return v;
}

std::shared_ptr<const OffloadAccelerator> fpga_matrix_units(const BackendConfig& config) {
  return std::make_shared<const FpgaMatrixUnits>(config);
}

std::vector<MemoryStructure> backend_memories(const BackendConfig& be) {
  const std::int64_t word_bytes = be.scalar_bytes();
  // A row feeds every copy of the array a block row a cycle (one word without an array).
  const MatrixUnitInstance* array = be.unit_for(trace::Op::Gemm);
  const std::int64_t row_words =
      array == nullptr ? 1 : std::int64_t(std::max(1, array->unit->tile())) * array->count;
  const std::int64_t row_bytes = word_bytes * row_words;
  MemoryStructure spm{"backend_spm", row_bytes * 8, (be.spm_bytes + row_bytes - 1) / row_bytes, 1};
  return {spm};
}

EDX_REGISTER_COMPONENT(
    OffloadAccelerator, FpgaMatrixUnits, "fpga_matrix_units",
    "matrix units on the FPGA sharing one scratchpad (paper Sec. VI-A, Fig. 14)");

}  // namespace edx::arch
