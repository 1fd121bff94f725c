#pragma once
// The paper's offload accelerator (Sec. VI-A, Fig. 14), kind `fpga_matrix_units`: matrix units on
// the FPGA (BackendConfig::units, each a registered MatrixUnit kind) sharing one scratchpad. A
// kernel's plan is its ops replayed on the units (accelerate_kernel, kernel_replay.hpp); its DES
// model is BackendAccelerator; its resources are the units', the "Misc." adders' and the SPM's
// (docs/MODEL.md, "Backend accelerator" and "Resources").
#include <memory>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/offload_accelerator.hpp"

namespace edx::arch {

class FpgaMatrixUnits final : public OffloadAccelerator {
 public:
  using Params = BackendConfig;
  /// Validates `config`.
  explicit FpgaMatrixUnits(const BackendConfig& config);

  std::string_view kind() const override { return "fpga_matrix_units"; }
  nlohmann::json params_json() const override { return config_.to_json(); }
  /// The instances of count > 0, in BackendConfig::units order.
  std::vector<std::string> resource_names() const override;
  std::unique_ptr<const OffloadPlan> plan(const trace::KernelRecord& kernel) const override;
  /// Plans with one OpTimingMemo for the run (kernel_replay.hpp).
  std::unique_ptr<OffloadPlanner> planner() const override;
  std::unique_ptr<OffloadModel> instantiate(sim::Simulator& sim) const override;
  /// Table II's building blocks: each unit instance (N.S.: one per offloaded kernel using it),
  /// the "Misc." adder (one per kernel that adds) and the operand SPM (one per kernel).
  std::vector<cost::CostEntry> cost_entries(const AcceleratorCostContext& context) const override;
  KernelMatrixFormat matrix_format() const override { return config_.matrix_format(); }
  std::int64_t local_memory_bytes() const override { return config_.spm_bytes; }
  trace::Precision precision() const override { return config_.precision; }

  const BackendConfig& config() const { return config_; }

 private:
  BackendConfig config_;
};

/// The paper's accelerator with `config` (code that builds a platform without YAML).
std::shared_ptr<const OffloadAccelerator> fpga_matrix_units(const BackendConfig& config = {});

/// The backend's memories from its unit sizes: the operand scratchpad (spm_bytes in rows of one
/// block row of the GEMM array's words, so the array reads a block row a cycle).
std::vector<MemoryStructure> backend_memories(const BackendConfig& be);

}  // namespace edx::arch
