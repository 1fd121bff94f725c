#include "arch/cost/energy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace edx::arch::cost {
namespace {

constexpr double kPico = 1e-12;

/// compute_j, memory_j and link_j of `a` (frame_energy's work-proportional terms).
void dynamic_parts(const FrameActivity& a, const PowerConfig& p, const ByteEnergies& b,
                   FrameEnergy& e) {
  const double op_pj = a.int8_ops * p.int8_op_pj + a.fixed_macs * p.fixed_mac_pj +
                       a.single_macs * p.single_mac_pj + a.double_macs * p.double_mac_pj;
  e.compute_j = p.fpga_dynamic_scale * p.fpga_energy_factor * op_pj * kPico;
  e.memory_j = (a.bram_bytes * b.on_chip_pj_per_byte + a.dram_bytes * p.dram_pj_per_byte) * kPico;
  e.link_j = a.link_bytes * b.link_pj_per_byte * kPico;
}

}  // namespace

nlohmann::json FrameEnergy::to_json() const {
  return {{"fpga_static_j", fpga_static_j}, {"host_j", host_j}, {"compute_j", compute_j},
          {"memory_j", memory_j},           {"link_j", link_j}, {"total_j", total_j}};
}

FrameEnergy frame_energy(const FrameActivity& a, const PowerConfig& p, const HostPower& host,
                         const ByteEnergies& b) {
  a.validate();  // `p` was validated where its platform was read (PowerConfig::from_yaml)
  FrameEnergy e;
  e.fpga_static_j = a.fpga_present ? p.fpga_static_w * a.frame_s : 0.0;
  e.host_j = p.host_power_scale *
             (host.active_w * a.host_busy_s + host.idle_w * (a.frame_s - a.host_busy_s));
  dynamic_parts(a, p, b, e);
  e.total_j = e.fpga_static_j + e.host_j + e.compute_j + e.memory_j + e.link_j;
  return e;
}

double dynamic_energy_j(const FrameActivity& a, const PowerConfig& p, const ByteEnergies& b) {
  FrameEnergy e;
  dynamic_parts(a, p, b, e);
  return e.compute_j + e.memory_j + e.link_j;
}

nlohmann::json ResourceEnergy::to_json() const {
  return {{"busy_s", busy_s},
          {"idle_s", idle_s},
          {"active_w", active_w},
          {"idle_w", idle_w},
          {"energy_j", energy_j}};
}

ResourceEnergy unit_energy(std::string name, double busy_s, double span_s, double dynamic_j,
                           const PowerConfig& power) {
  ResourceEnergy r;
  r.name = std::move(name);
  r.busy_s = std::max(0.0, busy_s);
  r.idle_s = std::max(0.0, span_s - r.busy_s);
  r.active_w = r.busy_s > 0 ? dynamic_j / r.busy_s : 0.0;
  r.idle_w = power.fpga_idle_fraction * r.active_w;
  // A unit with work but no recorded busy time (a run that does not track it) keeps its work.
  r.energy_j = r.busy_s > 0 ? r.busy_s * r.active_w + r.idle_s * r.idle_w : dynamic_j;
  return r;
}

}  // namespace edx::arch::cost
