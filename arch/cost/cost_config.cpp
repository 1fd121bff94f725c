#include "arch/cost/cost_config.hpp"

#include <map>

#include "arch/common/bounds.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch::cost {

const FieldList<CostConfig>& CostConfig::fields() {
  using C = CostConfig;
  const Bounds fraction = Bounds::at_least(0);
  static const FieldList<C> list = {
      field("frontend_lut_overhead", &C::frontend_lut_overhead, "",
            "control and glue LUTs as a fraction of the frontend datapath's (calibrated)",
            fraction),
      field("frontend_ff_overhead", &C::frontend_ff_overhead, "",
            "control and glue FFs as a fraction of the frontend datapath's (calibrated)", fraction),
      field("backend_lut_overhead", &C::backend_lut_overhead, "",
            "control and glue LUTs as a fraction of the backend datapath's (calibrated)", fraction),
      field("backend_ff_overhead", &C::backend_ff_overhead, "",
            "control and glue FFs as a fraction of the backend datapath's (calibrated)", fraction),
      field("ns_modes", &C::ns_modes, "", "modes of the no-sharing (N.S.) variant of Table III",
            Bounds::at_least(1)),
      field("ns_frontend_per_mode", &C::ns_frontend_per_mode, "",
            "N.S.: replicate the whole frontend per mode"),
      field("ns_fe_per_camera", &C::ns_fe_per_camera, "",
            "N.S.: also replicate FE (FD, IF, FC and their SBs) per camera"),
      field("ns_backend_per_kernel", &C::ns_backend_per_kernel, "",
            "N.S.: one set of backend units per kernel (Table II)"),
  };
  return list;
}

void CostConfig::validate() const { check_fields(*this, "cost", fields()); }

nlohmann::json CostConfig::to_json() const { return fields_to_json(*this, fields()); }

CostConfig CostConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  // Keys of `cost:` that became a component kind's own: the frontend units', the memory's.
  static const std::map<std::string, std::string> moved = {
      {"frontend_arithmetic", "frontend.units.IF.arithmetic and frontend.units.LSS.arithmetic"},
      {"if_separable", "frontend.units.IF.separable"},
      {"fc_angle_bins", "frontend.units.FC.angle_bins"},
      {"allow_bram18", "memory.allow_bram18 of the bram memory kind"},
      {"memory_read_muxes", "memory.read_muxes of the bram memory kind"},
  };
  YamlFields(node, where, "cost").refuse_moved(moved);
  return parse_section<CostConfig>(node, where, "cost");
}

const FieldList<PowerConfig>& PowerConfig::fields() {
  using C = PowerConfig;
  const Bounds non_negative = Bounds::at_least(0);
  static const FieldList<C> list = {
      field("fpga_static_w", &C::fpga_static_w, "W", "FPGA static power (assumed, XPE order)",
            non_negative),
      field("int8_op_pj", &C::int8_op_pj, "pJ", "8-bit add at 45 nm (Horowitz 2014)",
            bounds::energy_pj()),
      field("fixed_mac_pj", &C::fixed_mac_pj, "pJ", "16-bit multiply + 32-bit add at 45 nm",
            bounds::energy_pj()),
      field("single_mac_pj", &C::single_mac_pj, "pJ", "32-bit float multiply + add at 45 nm",
            bounds::energy_pj()),
      field("double_mac_pj", &C::double_mac_pj, "pJ", "64-bit float multiply + add (assumed 4x)",
            bounds::energy_pj()),
      field("fpga_energy_factor", &C::fpga_energy_factor, "",
            "FPGA over ASIC dynamic energy (Kuon and Rose 2007: 7-14x)", bounds::energy_scale()),
      field("dram_pj_per_byte", &C::dram_pj_per_byte, "pJ/byte", "DRAM access",
            bounds::energy_pj()),
      field("fpga_idle_fraction", &C::fpga_idle_fraction, "",
            "idle-but-clocked FPGA unit power over its busy power (assumed 0)",
            non_negative.at_most(1)),
      field("host_power_scale", &C::host_power_scale, "", "calibration hook (1: not calibrated)",
            bounds::energy_scale()),
      field("fpga_dynamic_scale", &C::fpga_dynamic_scale, "",
            "calibration hook (1: not calibrated)", bounds::energy_scale()),
  };
  return list;
}

void PowerConfig::validate() const { check_fields(*this, "power", fields()); }

nlohmann::json PowerConfig::to_json() const { return fields_to_json(*this, fields()); }

PowerConfig PowerConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  // Keys of `power:` that became the host processor's own and the memory's and link's (issue 40).
  static const std::map<std::string, std::string> moved = {
      {"host_active_w", "host.active_w"},
      {"host_idle_w", "host.idle_w"},
      {"bram_pj_per_byte", "memory.pj_per_byte of the memory kind"},
      {"link_pj_per_byte", "link.pj_per_byte of the link kind"},
  };
  YamlFields(node, where, "power").refuse_moved(moved);
  return parse_section<PowerConfig>(node, where, "power");
}

}  // namespace edx::arch::cost
