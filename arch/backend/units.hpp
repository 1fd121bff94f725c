#pragma once
// The five building blocks of the backend accelerator (paper Sec. VI-A, Table II, Fig. 14), one
// descriptor each: the one place that says which ops a unit serves, how many MAC lanes it has,
// which resource-report entry is its cost, and (computed from the kernels' ops, not typed in)
// which accelerable kernels use it. Cycles per op are op_timing's; LUT/FF/DSP per unit are
// arch/cost/unit_costs' (backend_unit_cost).
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

enum class BackendUnit { kMultiply, kDecompose, kInverse, kTranspose, kSubstitute };
inline constexpr std::size_t kBackendUnitCount = 5;
inline constexpr std::array<BackendUnit, kBackendUnitCount> kBackendUnits = {
    BackendUnit::kMultiply, BackendUnit::kDecompose, BackendUnit::kInverse, BackendUnit::kTranspose,
    BackendUnit::kSubstitute};

struct BackendUnitDescriptor {
  BackendUnit unit;
  std::string_view name;        ///< "multiply", ... (timelines, stats)
  std::string_view cost_entry;  ///< its row of the resource report ("gemm", ...)
  std::string_view what;        ///< Table II's building block
  std::vector<trace::Op> ops;   ///< the trace ops it serves
  /// MAC lanes (the energy model counts busy cycles x lanes as MACs; 0: no arithmetic).
  double (*mac_lanes)(const BackendConfig& config);
};

/// The five descriptors, in kBackendUnits order.
const std::array<BackendUnitDescriptor, kBackendUnitCount>& backend_units();
const BackendUnitDescriptor& backend_unit(BackendUnit unit);
/// The descriptor's name.
const char* to_string(BackendUnit unit);
/// The unit that serves `op`.
BackendUnit unit_of(trace::Op op);
/// The accelerable kernels (arch/kernels) whose ops use `unit` (Table II's columns), from their
/// derived ops: what the non-shared design replicates the unit for.
std::vector<std::string> kernels_using(BackendUnit unit);

}  // namespace edx::arch
