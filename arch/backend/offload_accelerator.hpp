#pragma once
// What the offload scheduler sends backend kernels to (docs/MODEL.md, "Components"): one
// interface, whose implementations are registered kinds selected by `backend: {kind: ...}`. The
// paper's is `fpga_matrix_units` (Sec. VI-A, Fig. 14: matrix units on the FPGA sharing a
// scratchpad; arch/backend/accelerators/fpga_matrix_units.cpp); a GPU or a DSP beside the CPU
// is another kind. The system model asks an accelerator four things:
//   plan(kernel)      what one invocation costs there, analytically: its compute time on an
//                     idle accelerator, whether its operands fit the accelerator's local memory
//                     and the DRAM traffic when they do not, its work by resource (energy);
//   instantiate(sim)  its DES model, which runs plans with its resources contending;
//   cost_entries()    its FPGA resources (LUT/FF/DSP/BRAM; none for fixed silicon), shared and
//                     as the no-sharing variant replicates them per kernel;
//   matrix_format()   how its operands cross the link (the transfers' sizes).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "arch/common/registry.hpp"
#include "arch/cost/energy_activity.hpp"
#include "arch/cost/resources.hpp"
#include "arch/kernels/kernels.hpp"
#include "arch/memory/bram.hpp"
#include "sim_core/engine.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// DRAM bytes a kernel run out of core reads and writes (its operands stream through the local
/// memory in tiles).
struct SpillTraffic {
  std::int64_t read_bytes = 0;
  std::int64_t write_bytes = 0;
  std::int64_t bytes() const { return read_bytes + write_bytes; }
};

/// One kernel invocation planned on an offload accelerator. Implementations derive from it to
/// keep what their DES model needs (the FPGA's op schedule); a plan runs only on a model of the
/// accelerator that made it.
struct OffloadPlan {
  virtual ~OffloadPlan() = default;
  std::string kernel;
  /// False when the accelerator cannot run it (an op it has no unit for): it stays on the host,
  /// its compute_s infinite, `message` says why.
  bool runnable = true;
  double compute_s = 0;  ///< on an idle accelerator, transfers not included
  /// compute_s by resource (resource_names() order): the time its work holds each on an idle
  /// accelerator (they add up to compute_s).
  std::vector<double> compute_s_by_resource;
  std::int64_t local_bytes = 0;   ///< the local memory its largest step needs
  bool fits_local_memory = true;  ///< local_bytes within the accelerator's local memory
  SpillTraffic spill;             ///< out of core: DRAM traffic (0 when it fits)
  std::string message;            ///< why it cannot run, or why it spills ("" otherwise)
  /// Its work by resource (resource_names() order): operations and local-memory bytes.
  std::vector<cost::FrameActivity> activity;
};

/// Costing an accelerator's FPGA resources needs from the platform: the kernels it serves, the
/// no-sharing rule, and how the platform's memory costs a structure.
struct AcceleratorCostContext {
  std::vector<std::string> offload;  ///< scheduler.offload
  bool ns_per_kernel = true;         ///< N.S.: a resource per kernel that uses it (cost:)
  std::function<cost::Resources(const MemoryStructure&)> memory_cost;
};

/// Where a kernel's time on an offload accelerator went, by resource (resource_names() order),
/// added to `ps` (2 entries per resource, its caller's to size): ps[2i] its work held resource
/// i (run), ps[2i + 1] it waited for resource i (wait: other kernels held it, or it ran on fewer
/// copies than planned). Run and wait over all resources add up to the kernel's time.
struct OffloadTimes {
  sim::Time* ps = nullptr;
  void run(std::size_t resource, sim::Time t) const { ps[2 * resource] += t; }
  void wait(std::size_t resource, sim::Time t) const { ps[2 * resource + 1] += t; }
};

/// The DES model of an offload accelerator on a sim::Simulator (destroyed before it).
class OffloadModel {
 public:
  virtual ~OffloadModel() = default;
  /// Runs `plan` (made by this model's accelerator, runnable; alive until the task completes).
  /// `label` names its timeline spans ("f12 kalman_gain"). `times` (optional): where its time
  /// went, by resource (the critical-path attribution of the system DES).
  virtual sim::Task<void> run(const OffloadPlan& plan, std::string label, OffloadTimes times) = 0;
  sim::Task<void> run(const OffloadPlan& plan, std::string label) {
    return run(plan, std::move(label), OffloadTimes{});
  }
  /// Resource `index` of resource_names() (its busy time is its utilization); nullptr when it
  /// is not a DES resource.
  virtual const sim::Resource* resource(std::size_t index) const = 0;
  /// Registers <prefix>.<resource>.busy per resource and the model's own counters.
  virtual void register_stats(sim::StatsRegistry& registry, const std::string& prefix) const = 0;
  /// Records its work as spans in `group` of `timeline` (optional).
  virtual void set_timeline(sim::Timeline& timeline, const std::string& group) = 0;
};

/// Plans one run's kernels (OffloadAccelerator::planner): the same plans as
/// OffloadAccelerator::plan, and may keep exact memos across the run's kernels (an op's cost per
/// shape). Not thread-safe: one per run.
class OffloadPlanner {
 public:
  virtual ~OffloadPlanner() = default;
  virtual std::unique_ptr<const OffloadPlan> plan(const trace::KernelRecord& kernel) = 0;
};

class OffloadAccelerator : public Component {
 public:
  static constexpr const char* kKindName = "offload accelerator";
  /// Its resources that work, draw power and report utilization, in a fixed order
  /// ("gemm", "decomposition", ...; the system names them "backend.<name>").
  virtual std::vector<std::string> resource_names() const = 0;
  /// `kernel` (its recorded ops, or those derived from its sizes) on this accelerator. Reads the
  /// kernel's name, m, n, k, detail and its ops' kinds, sizes, flags and batches only, never a
  /// host time: the system model plans each shape once and shares the plan (system_model.cpp).
  virtual std::unique_ptr<const OffloadPlan> plan(const trace::KernelRecord& kernel) const = 0;
  /// A planner for one run (alive while this accelerator is); the default calls plan().
  virtual std::unique_ptr<OffloadPlanner> planner() const {
    struct Forwarding final : OffloadPlanner {
      explicit Forwarding(const OffloadAccelerator& a) : accelerator(a) {}
      std::unique_ptr<const OffloadPlan> plan(const trace::KernelRecord& kernel) override {
        return accelerator.plan(kernel);
      }
      const OffloadAccelerator& accelerator;
    };
    return std::make_unique<Forwarding>(*this);
  }
  /// Its DES model on `sim`.
  virtual std::unique_ptr<OffloadModel> instantiate(sim::Simulator& sim) const = 0;
  /// Its FPGA resources, group "backend" (empty for an accelerator that is fixed silicon).
  virtual std::vector<cost::CostEntry> cost_entries(
      const AcceleratorCostContext& context) const = 0;
  /// How kernels' matrices cross the link (element bytes, the marginalization's shape).
  virtual KernelMatrixFormat matrix_format() const = 0;
  /// Bytes of its local memory for a kernel's operands (the FPGA's scratchpad).
  virtual std::int64_t local_memory_bytes() const = 0;
  /// The arithmetic it computes kernels in; a trace is simulated on it only at the same
  /// (meta precision, check_precision).
  virtual trace::Precision precision() const = 0;
};

/// The kind a platform's `backend:` has without `kind:` (the paper's).
inline constexpr const char* kDefaultOffloadKind = "fpga_matrix_units";

}  // namespace edx::arch
