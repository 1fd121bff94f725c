#pragma once
// The work a frame (or one unit's share of it) did on the platform, as the energy model counts
// it (arch/cost/energy.hpp, docs/MODEL.md "Energy"): operations by arithmetic, on-chip, DRAM and
// link bytes. Counted by each unit kind (arch/frontend/units/, arch/backend/units/) and summed.
#include <nlohmann/json.hpp>

namespace edx::arch::cost {

/// What one frame did.
struct FrameActivity {
  double frame_s = 0;      ///< t_frame: frame period (1 / throughput)
  double host_busy_s = 0;  ///< t_host: host computing within the frame (<= frame_s)
  bool fpga_present = true;
  double int8_ops = 0;    ///< pixel operations (adds, compares, |a − b|)
  double fixed_macs = 0;  ///< fixed-point multiply-accumulates
  double single_macs = 0;
  double double_macs = 0;
  double bram_bytes = 0;  ///< on-chip memory traffic
  double dram_bytes = 0;
  double link_bytes = 0;  ///< host <-> FPGA
  void validate() const;  ///< throws std::runtime_error naming the field
  nlohmann::json to_json() const;
};

}  // namespace edx::arch::cost
