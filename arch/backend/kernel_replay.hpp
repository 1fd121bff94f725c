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
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/op_timing.hpp"
#include "arch/link/frame_transfers.hpp"
#include "arch/link/link.hpp"
#include "arch/memory/scratchpad.hpp"
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

struct KernelAccelResult {
  std::string kernel;
  bool derived_ops = false;  ///< the trace had no ops: kernel_ops() derived them from the sizes
  /// Every op has a unit (else it stays on the host: no ops, seconds infinite).
  bool offloadable = true;
  std::int64_t cycles = 0;  ///< Σ op cycles
  double seconds = 0;       ///< Σ op cycles / its unit's clock
  /// Busy copy-cycles per instance (BackendConfig::units order): Σ cycles × copies of its ops.
  std::vector<std::int64_t> unit_busy_cycles;
  std::int64_t spm_bytes_needed = 0;    ///< max over ops of op_spm_bytes()
  std::int64_t spm_bytes_capacity = 0;  ///< config.spm_bytes
  bool fits_spm = true;                 ///< needed <= capacity (else it spills)
  std::string message;                  ///< why it spills ("" when it fits)
  int spilled_ops = 0;                  ///< ops run out of core
  SpillTraffic spill;                   ///< Σ op_spill_traffic over its ops (DRAM bytes)
  /// The SPM sized for this kernel's largest op (one region).
  ScratchpadSizing spm;
  std::vector<OpTiming> ops;
};

/// Replays `kernel` (validated config; kernel_ops() throws for a kernel without ops it cannot
/// derive). A kernel that does not fit is returned with fits_spm = false, its spill traffic, and
/// a message naming the kernel, its largest op, the bytes needed, the capacity and the spill; a
/// kernel with an op no unit serves with offloadable = false and a message naming the op.
KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel, const BackendConfig& config);

/// Time of a replayed kernel's spill traffic on an idle link (the accelerator's only configured
/// path to DRAM: Edx-Drone's AXI4 reads the PS DDR; Edx-Car's PCIe reaches host memory):
/// transfer_time(spill.read_bytes) + transfer_time(spill.write_bytes), serialized with the
/// kernel's compute (the conservative reading: no tile prefetch overlaps the units). Seconds;
/// 0 when the kernel fits.
double spill_seconds(const KernelAccelResult& plan, const Link& link);

}  // namespace edx::arch
