#pragma once
// One accelerable backend kernel replayed on the backend accelerator, analytically (no DES): its
// ops (kernel_ops(): recorded, or derived from the kernel's sizes) run on their units in trace
// order, each after the previous one (each consumes the previous one's result), so the kernel
// takes Σ op_cycles on an idle accelerator, Σ op_cycles / f_unit in time (each unit on its own
// clock). A kernel with an op no unit serves cannot be offloaded (offloadable false). The
// scratchpad holds the operands of the running op (Sec. VI-A); the kernel needs the largest of
// those, which is checked against spm_bytes. An op whose operands do not fit runs out of core:
// tiled at the SPM's capacity, its operands and result stream from and to DRAM (op_spill_traffic),
// which the system model puts on the link (spill_seconds), serialized with the kernel's compute
// (docs/MODEL.md, "SPM spills").
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/link/link.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// One op of a replayed kernel.
struct OpTiming {
  trace::OpRecord op;
  std::size_t unit = 0;          ///< its instance: index into BackendConfig::units
  int copies = 1;                ///< the instance's copies sharing it (its count)
  std::int64_t start_cycle = 0;  ///< from the kernel's start, in its unit's cycles
  std::int64_t cycles = 0;       ///< op_cycles()
  std::int64_t spm_bytes = 0;    ///< op_spm_bytes()
  SpillTraffic spill;            ///< op_spill_traffic(): zero when it fits the SPM
};

/// The plan of the paper's accelerator (OffloadPlan's fields: kernel; runnable, false when an op
/// has no unit: compute_s infinite; compute_s = Σ op cycles / its unit's clock; local_bytes = the
/// largest op's SPM bytes, fits_local_memory against spm_bytes, spill = Σ op_spill_traffic;
/// activity per unit of count > 0: its MACs (busy copy-cycles × MAC lanes, at its precision) and
/// its ops' SPM bytes).
struct KernelAccelResult final : OffloadPlan {
  bool derived_ops = false;  ///< the trace had no ops: kernel_ops() derived them from the sizes
  std::int64_t cycles = 0;   ///< Σ op cycles
  /// Busy copy-cycles per instance (BackendConfig::units order): Σ cycles × copies of its ops.
  std::vector<std::int64_t> unit_busy_cycles;
  std::int64_t spm_bytes_capacity = 0;  ///< config.spm_bytes
  int spilled_ops = 0;                  ///< ops run out of core
  std::vector<OpTiming> ops;
};

/// Replays `kernel` (validated config; kernel_ops() throws for a kernel without ops it cannot
/// derive). A kernel that does not fit is returned with fits_local_memory = false, its spill
/// traffic, and a message naming the kernel, its largest op, the bytes needed, the capacity and
/// the spill; a kernel with an op no unit serves with runnable = false and a message naming the
/// op.
KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel, const BackendConfig& config);

/// An op's cost on its instance: op_cycles (on all the instance's copies), op_spm_bytes and
/// op_spill_traffic.
struct OpCost {
  std::int64_t cycles = 0;
  std::int64_t spm_bytes = 0;
  SpillTraffic spill;
};

/// Exact memo of OpCost for one BackendConfig (one run's planner): the three functions read only
/// the op's kind, m, n, k, flags and batch (never host_ns) and the config, so the ops of one shape
/// share an entry: a trace repeats few shapes (the block rows of a blocked substitution, the same
/// kernel every frame). Key = (op, m, n, k, flags, batch); an op that throws is not stored. Not
/// thread-safe; use it with the config it was first used with only.
class OpTimingMemo {
 public:
  /// The cost of `op` on `unit` of `config` (the instance serving op.op).
  const OpCost& cost(const trace::OpRecord& op, const MatrixUnitInstance& unit,
                     const BackendConfig& config);

 private:
  struct Key {
    trace::Op op;
    std::int64_t m, n, k;
    std::uint32_t flags;
    std::int64_t batch;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const;
  };
  std::unordered_map<Key, OpCost, KeyHash> costs_;
};

/// accelerate_kernel with its ops' costs from `memo` (the same result).
KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel, const BackendConfig& config,
                                    OpTimingMemo& memo);

/// Time of a replayed kernel's spill traffic on an idle link (the accelerator's only configured
/// path to DRAM: Edx-Drone's AXI4 reads the PS DDR; Edx-Car's PCIe reaches host memory):
/// transfer_time(spill.read_bytes) + transfer_time(spill.write_bytes), serialized with the
/// kernel's compute (the conservative reading: no tile prefetch overlaps the units). Seconds;
/// 0 when the kernel fits.
double spill_seconds(const OffloadPlan& plan, const Link& link);

}  // namespace edx::arch
