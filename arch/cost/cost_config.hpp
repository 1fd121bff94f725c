#pragma once
// Configuration of the resource and energy models (docs/MODEL.md, "Cost"): the `cost:` and
// `power:` sections of a platform YAML. The backend unit sizes are the backend's own
// (arch/backend BackendConfig, `backend:`). Every field has a default and its source in
// docs/MODEL.md; unknown keys are errors.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/cost/resources.hpp"
#include "common/config_fields.hpp"

namespace YAML {
class Node;
}

namespace edx::arch::cost {

/// `cost:` section: knobs of the resource model.
struct CostConfig {
  /// Control and glue logic (FSMs, AXI/DMA ports, handshakes, pipeline registers, fan-out) as a
  /// fraction of each group's datapath LUTs / FFs (units and memories). Calibrated on Edx-Car's
  /// Table III LUT / FF totals x frontend shares (calibrate_control_overheads, docs/MODEL.md).
  double frontend_lut_overhead = 0.051;
  double frontend_ff_overhead = 0.350;
  double backend_lut_overhead = 0.480;
  double backend_ff_overhead = 1.963;
  // The no-sharing ("N.S.") variant of Table III.
  int ns_modes = 3;                  ///< registration, VIO, SLAM: one frontend each
  bool ns_frontend_per_mode = true;  ///< replicate the whole frontend per mode
  /// Also replicate FE (FD, IF, FC + their SBs) per camera. Off: the paper's N.S. is "without
  /// sharing ... across the three modes" (Sec. VII-B), and on overshoots its N.S. (docs/MODEL.md).
  bool ns_fe_per_camera = false;
  bool ns_backend_per_kernel = true;  ///< one set of units per kernel (Table II)

  /// Every key of `cost:` (docs/CONFIG.md). The units' arithmetic is each unit's own
  /// (frontend.units.IF.arithmetic, backend.units.<name>.precision); how memories map onto
  /// blocks is the memory kind's (`memory:`).
  static const FieldList<CostConfig>& fields();
  void validate() const;  ///< throws std::runtime_error "cost.<field>: expected ..."
  nlohmann::json to_json() const;
  /// Errors name file, line and key: "car.yaml:40: cost.ns_modes: expected an integer >= 1".
  static CostConfig from_yaml(const YAML::Node& node, const std::string& where);
};

/// `power:` section: static and dynamic power of the FPGA, energies per operation and per byte,
/// the calibration hooks (docs/MODEL.md gives each one's source or marks it assumed). The host's
/// power is the host processor's own (`host:`, arch/host/host_processor.hpp).
struct PowerConfig {
  double fpga_static_w = 0.8;  ///< assumed: XPE-order static power of a large 28 nm device
  // Per-operation energies at 45 nm (Horowitz, ISSCC 2014), scaled by fpga_energy_factor.
  double int8_op_pj = 0.03;          ///< 8-bit add
  double fixed_mac_pj = 1.0;         ///< 16-bit multiply + 32-bit add (between 8- and 32-bit mult)
  double single_mac_pj = 4.6;        ///< 32-bit FP mult 3.7 + add 0.9
  double double_mac_pj = 18.4;       ///< assumed 4x single (53-bit vs 24-bit mantissa multiplier)
  double fpga_energy_factor = 10.0;  ///< FPGA vs ASIC dynamic energy (Kuon and Rose 2007: 7-14x)
  // Per-byte energy of DRAM (the on-chip memory's and the link's are their kinds':
  // memory.pj_per_byte, link.pj_per_byte).
  double dram_pj_per_byte = 160.0;  ///< 20 pJ/bit (Horowitz 2014: 1.3-2.6 nJ per 64 bits)
  /// Idle-but-clocked power of an FPGA unit (frontend task unit, backend matrix unit) as a
  /// fraction of its mean power while busy (docs/MODEL.md, "Energy per resource"). Assumed 0:
  /// fpga_static_w covers the device's leakage, and no source in the repo sizes a unit's clock
  /// power; not calibrated.
  double fpga_idle_fraction = 0.0;
  // Calibration hooks against Edx-Car's 1.9 J -> 0.5 J per frame (not calibrated: 1).
  double host_power_scale = 1.0;
  double fpga_dynamic_scale = 1.0;

  /// Every key of `power:` (docs/CONFIG.md).
  static const FieldList<PowerConfig>& fields();
  void validate() const;  ///< throws std::runtime_error "power.<field>: expected ..."
  nlohmann::json to_json() const;
  /// Errors name file, line and key; a key that moved to the host is refused with where it went.
  static PowerConfig from_yaml(const YAML::Node& node, const std::string& where);
};

}  // namespace edx::arch::cost
