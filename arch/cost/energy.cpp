#include "arch/cost/energy.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace edx::arch::cost {
namespace {

constexpr double kPico = 1e-12;

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::runtime_error(fmt::format("activity.{}: expected {}", field, expected));
}

}  // namespace

void FrameActivity::validate() const {
  require(frame_s > 0, "frame_s", "a frame time > 0 s");
  require(host_busy_s >= 0 && host_busy_s <= frame_s, "host_busy_s", "a time in [0, frame_s]");
  require(int8_ops >= 0, "int8_ops", "a count >= 0");
  require(fixed_macs >= 0, "fixed_macs", "a count >= 0");
  require(single_macs >= 0, "single_macs", "a count >= 0");
  require(double_macs >= 0, "double_macs", "a count >= 0");
  require(bram_bytes >= 0, "bram_bytes", "a count >= 0");
  require(dram_bytes >= 0, "dram_bytes", "a count >= 0");
  require(link_bytes >= 0, "link_bytes", "a count >= 0");
}

nlohmann::json FrameActivity::to_json() const {
  return {{"frame_s", frame_s},           {"host_busy_s", host_busy_s},
          {"fpga_present", fpga_present}, {"int8_ops", int8_ops},
          {"fixed_macs", fixed_macs},     {"single_macs", single_macs},
          {"double_macs", double_macs},   {"bram_bytes", bram_bytes},
          {"dram_bytes", dram_bytes},     {"link_bytes", link_bytes}};
}

nlohmann::json FrameEnergy::to_json() const {
  return {{"fpga_static_j", fpga_static_j}, {"host_j", host_j}, {"compute_j", compute_j},
          {"memory_j", memory_j},           {"link_j", link_j}, {"total_j", total_j}};
}

FrameEnergy frame_energy(const FrameActivity& a, const PowerConfig& p) {
  a.validate();
  p.validate();
  FrameEnergy e;
  e.fpga_static_j = a.fpga_present ? p.fpga_static_w * a.frame_s : 0.0;
  e.host_j = p.host_power_scale *
             (p.host_active_w * a.host_busy_s + p.host_idle_w * (a.frame_s - a.host_busy_s));
  const double op_pj = a.int8_ops * p.int8_op_pj + a.fixed_macs * p.fixed_mac_pj +
                       a.single_macs * p.single_mac_pj + a.double_macs * p.double_mac_pj;
  e.compute_j = p.fpga_dynamic_scale * p.fpga_energy_factor * op_pj * kPico;
  e.memory_j = (a.bram_bytes * p.bram_pj_per_byte + a.dram_bytes * p.dram_pj_per_byte) * kPico;
  e.link_j = a.link_bytes * p.link_pj_per_byte * kPico;
  e.total_j = e.fpga_static_j + e.host_j + e.compute_j + e.memory_j + e.link_j;
  return e;
}

std::vector<PaperComparison> compare_energy_to_edx_car(double baseline_j, double accelerated_j) {
  const double reduction = baseline_j > 0 ? 1.0 - accelerated_j / baseline_j : 0.0;
  const auto row = [](const char* name, double paper, double simulated) {
    return PaperComparison{name, paper, simulated, simulated / paper - 1.0};
  };
  return {row("baseline_j_per_frame", EdxCarEnergy::kBaselineJ, baseline_j),
          row("accelerated_j_per_frame", EdxCarEnergy::kAcceleratedJ, accelerated_j),
          row("energy_reduction", EdxCarEnergy::kReduction, reduction)};
}

}  // namespace edx::arch::cost
