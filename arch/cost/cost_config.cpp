#include "arch/cost/cost_config.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch::cost {
namespace {

void require(bool ok, const char* section, const char* field, const std::string& expected) {
  if (!ok) {
    throw std::runtime_error(fmt::format("{}.{}: expected {}", section, field, expected));
  }
}

/// Runs validate() and turns its "section.key: message" into a file:line error.
template <typename Config>
void validate_at(const Config& c, const YamlFields& f, const std::string& section) {
  try {
    c.validate();
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    const std::size_t start = section.size() + 1;
    const std::size_t colon = message.find(':');
    f.fail(message.substr(start, colon - start), message.substr(colon + 2));
  }
}

}  // namespace

Arithmetic CostConfig::frontend_arith() const {
  return parse_arithmetic(frontend_arithmetic, "cost.frontend_arithmetic");
}

Arithmetic CostConfig::backend_arith() const {
  return parse_arithmetic(backend_precision, "cost.backend_precision");
}

void CostConfig::validate() const {
  const char* s = "cost";
  require(frontend_arithmetic == "fixed" || frontend_arithmetic == "single", s,
          "frontend_arithmetic", "fixed or single");
  require(backend_precision == "single" || backend_precision == "double", s, "backend_precision",
          "single or double");
  require(fc_angle_bins >= 1, s, "fc_angle_bins", "an integer >= 1");
  require(frontend_lut_overhead >= 0, s, "frontend_lut_overhead", "a fraction >= 0");
  require(frontend_ff_overhead >= 0, s, "frontend_ff_overhead", "a fraction >= 0");
  require(backend_lut_overhead >= 0, s, "backend_lut_overhead", "a fraction >= 0");
  require(backend_ff_overhead >= 0, s, "backend_ff_overhead", "a fraction >= 0");
  require(ns_modes >= 1, s, "ns_modes", "an integer >= 1");
}

nlohmann::json CostConfig::to_json() const {
  return {{"frontend_arithmetic", frontend_arithmetic},
          {"if_separable", if_separable},
          {"fc_angle_bins", fc_angle_bins},
          {"backend_precision", backend_precision},
          {"frontend_lut_overhead", frontend_lut_overhead},
          {"frontend_ff_overhead", frontend_ff_overhead},
          {"backend_lut_overhead", backend_lut_overhead},
          {"backend_ff_overhead", backend_ff_overhead},
          {"memory_read_muxes", memory_read_muxes},
          {"allow_bram18", allow_bram18},
          {"ns_modes", ns_modes},
          {"ns_frontend_per_mode", ns_frontend_per_mode},
          {"ns_fe_per_camera", ns_fe_per_camera},
          {"ns_backend_per_kernel", ns_backend_per_kernel}};
}

CostConfig CostConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  CostConfig c;
  YamlFields f(node, where, "cost");
  f.read("frontend_arithmetic", c.frontend_arithmetic);
  f.read("if_separable", c.if_separable);
  f.read("fc_angle_bins", c.fc_angle_bins, 1);
  f.read("backend_precision", c.backend_precision);
  f.read("frontend_lut_overhead", c.frontend_lut_overhead, -1e-12);
  f.read("frontend_ff_overhead", c.frontend_ff_overhead, -1e-12);
  f.read("backend_lut_overhead", c.backend_lut_overhead, -1e-12);
  f.read("backend_ff_overhead", c.backend_ff_overhead, -1e-12);
  f.read("memory_read_muxes", c.memory_read_muxes);
  f.read("allow_bram18", c.allow_bram18);
  f.read("ns_modes", c.ns_modes, 1);
  f.read("ns_frontend_per_mode", c.ns_frontend_per_mode);
  f.read("ns_fe_per_camera", c.ns_fe_per_camera);
  f.read("ns_backend_per_kernel", c.ns_backend_per_kernel);
  f.finish();
  validate_at(c, f, "cost");
  return c;
}

void PowerConfig::validate() const {
  const char* s = "power";
  require(fpga_static_w >= 0, s, "fpga_static_w", "a power >= 0 W");
  require(host_active_w >= 0, s, "host_active_w", "a power >= 0 W");
  require(host_idle_w >= 0 && host_idle_w <= host_active_w, s, "host_idle_w",
          "a power in [0, host_active_w] W");
  require(int8_op_pj >= 0, s, "int8_op_pj", "an energy >= 0 pJ");
  require(fixed_mac_pj >= 0, s, "fixed_mac_pj", "an energy >= 0 pJ");
  require(single_mac_pj >= 0, s, "single_mac_pj", "an energy >= 0 pJ");
  require(double_mac_pj >= 0, s, "double_mac_pj", "an energy >= 0 pJ");
  require(fpga_energy_factor > 0, s, "fpga_energy_factor", "a factor > 0");
  require(bram_pj_per_byte >= 0, s, "bram_pj_per_byte", "an energy >= 0 pJ");
  require(dram_pj_per_byte >= 0, s, "dram_pj_per_byte", "an energy >= 0 pJ");
  require(link_pj_per_byte >= 0, s, "link_pj_per_byte", "an energy >= 0 pJ");
  require(host_power_scale > 0, s, "host_power_scale", "a factor > 0");
  require(fpga_dynamic_scale > 0, s, "fpga_dynamic_scale", "a factor > 0");
}

nlohmann::json PowerConfig::to_json() const {
  return {{"fpga_static_w", fpga_static_w},
          {"host_active_w", host_active_w},
          {"host_idle_w", host_idle_w},
          {"int8_op_pj", int8_op_pj},
          {"fixed_mac_pj", fixed_mac_pj},
          {"single_mac_pj", single_mac_pj},
          {"double_mac_pj", double_mac_pj},
          {"fpga_energy_factor", fpga_energy_factor},
          {"bram_pj_per_byte", bram_pj_per_byte},
          {"dram_pj_per_byte", dram_pj_per_byte},
          {"link_pj_per_byte", link_pj_per_byte},
          {"host_power_scale", host_power_scale},
          {"fpga_dynamic_scale", fpga_dynamic_scale}};
}

PowerConfig PowerConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  PowerConfig c;
  YamlFields f(node, where, "power");
  f.read("fpga_static_w", c.fpga_static_w, -1e-12);
  f.read("host_active_w", c.host_active_w, -1e-12);
  f.read("host_idle_w", c.host_idle_w, -1e-12);
  f.read("int8_op_pj", c.int8_op_pj, -1e-12);
  f.read("fixed_mac_pj", c.fixed_mac_pj, -1e-12);
  f.read("single_mac_pj", c.single_mac_pj, -1e-12);
  f.read("double_mac_pj", c.double_mac_pj, -1e-12);
  f.read("fpga_energy_factor", c.fpga_energy_factor, 0.0);
  f.read("bram_pj_per_byte", c.bram_pj_per_byte, -1e-12);
  f.read("dram_pj_per_byte", c.dram_pj_per_byte, -1e-12);
  f.read("link_pj_per_byte", c.link_pj_per_byte, -1e-12);
  f.read("host_power_scale", c.host_power_scale, 0.0);
  f.read("fpga_dynamic_scale", c.fpga_dynamic_scale, 0.0);
  f.finish();
  validate_at(c, f, "power");
  return c;
}

}  // namespace edx::arch::cost
