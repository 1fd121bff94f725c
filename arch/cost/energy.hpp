#pragma once
// Energy per frame (docs/MODEL.md, "Energy"):
//
//   E = P_fpga_static·t_frame                                       (when an FPGA is present)
//     + s_host·(P_host_active·t_host + P_host_idle·(t_frame − t_host))
//     + s_fpga·f_fpga·(n_int8·e_int8 + n_fixed·e_fixed + n_single·e_single + n_double·e_double)
//     + b_bram·e_bram + b_dram·e_dram + b_link·e_link
//
// with the host's package power (HostPower: P_host_active = active_w, P_host_idle = idle_w, the
// host processor's own, `host:`), the constants of PowerConfig (s_host = host_power_scale,
// s_fpga = fpga_dynamic_scale, f_fpga = fpga_energy_factor; energies in pJ) and the per-byte
// energies of the platform's components (ByteEnergies: e_bram its memory kind's, e_link its link
// kind's). The paper's Edx-Car
// figures (1.9 J -> 0.5 J per frame, −73.7 %, Sec. VII-C) are paper-check targets
// (reports/paper_targets.yaml); nothing is calibrated on them.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/cost/cost_config.hpp"
#include "arch/cost/energy_activity.hpp"
#include "arch/cost/resource_report.hpp"
#include "arch/host/host_processor.hpp"

namespace edx::arch::cost {

/// Energies per byte of the platform's components, pJ: e_bram of its on-chip memory
/// (OnChipMemory::pj_per_byte, `memory.pj_per_byte`) and e_link of its link (Link::pj_per_byte,
/// `link.pj_per_byte`). DRAM's is PowerConfig::dram_pj_per_byte.
struct ByteEnergies {
  double on_chip_pj_per_byte = 0;
  double link_pj_per_byte = 0;
};

struct FrameEnergy {
  double fpga_static_j = 0;
  double host_j = 0;     ///< active + idle
  double compute_j = 0;  ///< operations on the FPGA
  double memory_j = 0;   ///< BRAM + DRAM
  double link_j = 0;
  double total_j = 0;
  nlohmann::json to_json() const;
};

FrameEnergy frame_energy(const FrameActivity& activity, const PowerConfig& power,
                         const HostPower& host, const ByteEnergies& bytes);

/// The work-proportional part of frame_energy (compute + memory + link), J: what a unit's ops
/// and bytes cost, without static or host power. `activity` need not have a frame time.
double dynamic_energy_j(const FrameActivity& activity, const PowerConfig& power,
                        const ByteEnergies& bytes);

/// One resource's energy over a run (docs/MODEL.md, "Energy per resource"):
///   E = busy_s · active_w + idle_s · idle_w
struct ResourceEnergy {
  std::string name;  ///< as SystemRun's resources: "frontend.FD", "backend.multiply", ...
  double busy_s = 0, idle_s = 0;
  double active_w = 0, idle_w = 0;
  double energy_j = 0;
  nlohmann::json to_json() const;
};

/// An FPGA unit that spent `dynamic_j` on its work in `busy_s` of a run `span_s` long (capacity
/// 1): active_w = dynamic_j / busy_s (0 when never busy), idle_w = fpga_idle_fraction · active_w,
/// idle_s = span_s − busy_s, so E = dynamic_j · (1 + f_idle · idle_s / busy_s).
ResourceEnergy unit_energy(std::string name, double busy_s, double span_s, double dynamic_j,
                           const PowerConfig& power);

}  // namespace edx::arch::cost
