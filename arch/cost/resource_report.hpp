#pragma once
// The FPGA resource report of a platform (paper Sec. VII-B, Table III; docs/MODEL.md): every
// unit and memory with its LUT/FF/DSP/BRAM, per-group totals (frontend, backend) and the memory
// subtotal, the control overhead of each group, totals and utilization against the device, and
// the no-sharing ("N.S.") variant: each entry carries how many copies a design without sharing
// would instantiate.
//
// N.S. copies (CostConfig):
//   FE units and memories (FD, IF, FC; the fe./fc. stencil buffers, the FD->FC FIFO):
//       (ns_fe_per_camera ? 2 : 1) x (ns_frontend_per_mode ? ns_modes : 1)   (default 1 x 3)
//   the rest of the frontend (MO, DR, DC, LSS, their memories, the SPM): ns_modes or 1
//   backend units (ns_backend_per_kernel): the offloaded kernels (scheduler.offload) using them,
//       from their ops; with the paper's three (Table II): GEMM 3 (projection, Kalman gain,
//       marginalization), decomposition, transpose, substitution 2, inverse 1; misc (its adder)
//       one per kernel that adds (2 of the three); the backend SPM one per kernel (3).
//   control overhead: the group's overhead fraction of its N.S. datapath.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/backend/offload_accelerator.hpp"
#include "arch/cost/cost_config.hpp"
#include "arch/cost/resources.hpp"
#include "arch/frontend/frontend_config.hpp"
#include "arch/memory/bram.hpp"
#include "arch/memory/on_chip_memory.hpp"

namespace edx::arch::cost {

/// Totals of a set of entries, shared and N.S.
struct CostTotals {
  Resources shared, ns;
  nlohmann::json to_json() const;
};

struct ResourceReport {
  std::vector<CostEntry> entries;
  CostTotals frontend, backend, memories, total;
  Device device;
  Resources utilization;     ///< total.shared / device totals, each in [0, ...)
  Resources ns_utilization;  ///< total.ns / device totals
  Resources frontend_share;  ///< frontend.shared / total.shared (Sec. VII-B's percentages)
  double bram_mib = 0;       ///< total.shared.bram x 4096 B / 2^20 (the paper's "MB")
  double ns_bram_mib = 0;
  bool fits = true;  ///< every shared resource within the device
  nlohmann::json to_json() const;
};

/// Builds the report. Memories cost what the platform's `memory` kind says (their blocks and
/// read muxes). `frontend_memories`: the frontend memory plan's structures
/// (FrontendMemoryPlan::bram.structures[i].structure), by their plan names (fe.L<l>..., fc...,
/// fd_to_fc: FE; everything else: SM/TM/SPM).
/// `be`: the offload accelerator, whose cost_entries() are the backend group. `offload`: the
/// kernels it serves (scheduler.offload), whose use of each unit the N.S. variant replicates it
/// for.
ResourceReport build_resource_report(const FrontendConfig& fe, const OffloadAccelerator& be,
                                     const CostConfig& cost, const OnChipMemory& memory,
                                     const std::vector<MemoryStructure>& frontend_memories,
                                     const Device& device,
                                     const std::vector<std::string>& offload = paper_offload_set());

/// The frontend memory structures of an `edx simulate --json` result
/// (frontend.memory.bram.structures); throws std::runtime_error naming `where` and the missing key.
std::vector<MemoryStructure> frontend_memories_from_simulate_json(const nlohmann::json& result,
                                                                  const std::string& where);

// --- Calibration against Table III (Edx-Car only) ---

/// One paper figure beside the simulated one.
struct PaperComparison {
  std::string figure;
  double paper = 0, simulated = 0;
  double relative_error = 0;  ///< simulated / paper − 1
  nlohmann::json to_json() const;
};

/// Edx-Car's Table III and Sec. VII-B figures: LUT 350 671, FF 239 347, DSP 1 284, BRAM 5.0 MB;
/// utilization 80.9 / 27.6 / 35.6 / 87.5 %; N.S. 795 604 / 628 346 / 3 628 / 13.2 MB; frontend
/// share 83.2 / 62.2 / 80.2 / 73.5 %.
struct EdxCarTableIII {
  static constexpr Resources kShared{350671, 239347, 1284, 0};
  static constexpr double kBramMb = 5.0;
  static constexpr Resources kUtilization{0.809, 0.276, 0.356, 0.875};
  static constexpr Resources kNs{795604, 628346, 3628, 0};
  static constexpr double kNsBramMb = 13.2;
  static constexpr Resources kFrontendShare{0.832, 0.622, 0.802, 0.735};
};

/// Every Table III figure of Edx-Car against `report` (shared, utilization, N.S., shares).
std::vector<PaperComparison> compare_to_table_iii(const ResourceReport& report);

/// The four control-overhead fractions that make the frontend's and the backend's LUT and FF
/// equal Table III's totals x frontend shares: overhead = target / datapath − 1 per group and
/// resource, the datapath being the group's units and memories (its control entry left out);
/// clamped at 0 when the datapath alone exceeds the target. Returns `cost` with them set.
CostConfig calibrate_control_overheads(const ResourceReport& report, CostConfig cost);

}  // namespace edx::arch::cost
