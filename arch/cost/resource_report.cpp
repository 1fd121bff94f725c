#include "arch/cost/resource_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace edx::arch::cost {
namespace {

/// FE (time-shared between cameras) memories of the frontend plan, by name.
bool is_fe_memory(const std::string& name) {
  return name.starts_with("fe.") || name.starts_with("fc.") || name == "fd_to_fc";
}

CostTotals sum(const std::vector<CostEntry>& entries, const std::string& group,
               const std::string& kind) {
  CostTotals t;
  for (const CostEntry& e : entries) {
    if ((group.empty() || e.group == group) && (kind.empty() || e.kind == kind)) {
      t.shared += e.shared;
      t.ns += e.ns;
    }
  }
  return t;
}

/// The control entry of a group: LUT and FF overhead fractions of its datapath (units and
/// memories), shared and N.S.
CostEntry control_entry(const std::vector<CostEntry>& entries, const std::string& group,
                        double lut_overhead, double ff_overhead) {
  const CostTotals datapath = sum(entries, group, "");
  CostEntry e{"control", group, "control", {}, 1, {}};
  e.shared.lut = lut_overhead * datapath.shared.lut;
  e.shared.ff = ff_overhead * datapath.shared.ff;
  e.ns.lut = lut_overhead * datapath.ns.lut;
  e.ns.ff = ff_overhead * datapath.ns.ff;
  return e;
}

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

Resources divide(const Resources& a, const Resources& b) {
  return {ratio(a.lut, b.lut), ratio(a.ff, b.ff), ratio(a.dsp, b.dsp), ratio(a.bram, b.bram)};
}

Resources device_totals(const Device& d) {
  return {double(d.luts), double(d.flip_flops), double(d.dsps), double(d.bram36_blocks)};
}

double mib_of_blocks(double blocks) { return to_mib(bytes_of_blocks(blocks, false)); }

}  // namespace

nlohmann::json CostTotals::to_json() const {
  return {{"shared", shared.to_json()}, {"ns", ns.to_json()}};
}

nlohmann::json ResourceReport::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const CostEntry& e : entries) list.push_back(e.to_json());
  return {{"device", device.to_json()},
          {"entries", list},
          {"frontend", frontend.to_json()},
          {"backend", backend.to_json()},
          {"memories", memories.to_json()},
          {"total", total.to_json()},
          {"utilization", utilization.to_json()},
          {"ns_utilization", ns_utilization.to_json()},
          {"frontend_share", frontend_share.to_json()},
          {"bram_mib", bram_mib},
          {"ns_bram_mib", ns_bram_mib},
          {"fits", fits}};
}

ResourceReport build_resource_report(const FrontendConfig& fe, const OffloadAccelerator& be,
                                     const CostConfig& cost, const OnChipMemory& memory,
                                     const std::vector<MemoryStructure>& frontend_memories,
                                     const Device& device,
                                     const std::vector<std::string>& offload) {
  fe.validate();
  cost.validate();
  const double modes = cost.ns_frontend_per_mode ? cost.ns_modes : 1;
  const double fe_copies = modes * (cost.ns_fe_per_camera ? 2 : 1);

  ResourceReport r;
  r.device = device;
  auto& v = r.entries;
  // The FE engine's units (FD, IF, FC) are replicated per camera too without sharing.
  for (const FrontendUnitInstance& u : fe.units) {
    const trace::Task task = u.unit->task();
    const bool fe_engine =
        task == trace::Task::FD || task == trace::Task::IF || task == trace::Task::FC;
    v.push_back(CostEntry::replicated(u.name, "frontend", "unit", u.unit->resources(fe) * u.count,
                                      fe_engine ? fe_copies : modes));
  }
  for (const MemoryStructure& s : frontend_memories) {
    s.validate();
    v.push_back(CostEntry::replicated(s.name, "frontend", "memory", memory.cost(s),
                                      is_fe_memory(s.name) ? fe_copies : modes));
  }
  // The offload accelerator's own entries (group "backend"; the N.S. copies per kernel).
  for (CostEntry& e :
       be.cost_entries({offload, cost.ns_backend_per_kernel,
                        [&memory](const MemoryStructure& s) { return memory.cost(s); }})) {
    v.push_back(std::move(e));
  }
  const CostEntry fe_control =
      control_entry(v, "frontend", cost.frontend_lut_overhead, cost.frontend_ff_overhead);
  const CostEntry be_control =
      control_entry(v, "backend", cost.backend_lut_overhead, cost.backend_ff_overhead);
  v.push_back(fe_control);
  v.push_back(be_control);

  r.frontend = sum(v, "frontend", "");
  r.backend = sum(v, "backend", "");
  r.memories = sum(v, "", "memory");
  r.total = sum(v, "", "");
  const Resources capacity = device_totals(device);
  r.utilization = divide(r.total.shared, capacity);
  r.ns_utilization = divide(r.total.ns, capacity);
  r.frontend_share = divide(r.frontend.shared, r.total.shared);
  r.bram_mib = mib_of_blocks(r.total.shared.bram);
  r.ns_bram_mib = mib_of_blocks(r.total.ns.bram);
  for (int i = 0; i < 4; ++i) r.fits = r.fits && r.total.shared[i] <= capacity[i];
  return r;
}

std::vector<MemoryStructure> frontend_memories_from_simulate_json(const nlohmann::json& result,
                                                                  const std::string& where) {
  const nlohmann::json::json_pointer path("/frontend/memory/bram/structures");
  if (!result.contains(path) || !result.at(path).is_array()) {
    throw std::runtime_error(
        fmt::format("{}: expected frontend.memory.bram.structures (edx simulate --json)", where));
  }
  std::vector<MemoryStructure> out;
  for (const nlohmann::json& usage : result.at(path)) {
    const nlohmann::json& s = usage.at("structure");
    out.push_back({s.at("name").get<std::string>(), s.at("width_bits").get<std::int64_t>(),
                   s.at("depth_words").get<std::int64_t>(), s.at("count").get<std::int64_t>()});
  }
  return out;
}

nlohmann::json PaperComparison::to_json() const {
  return {{"figure", figure},
          {"paper", paper},
          {"simulated", simulated},
          {"relative_error", relative_error}};
}

std::vector<PaperComparison> compare_to_table_iii(const ResourceReport& report) {
  using T = EdxCarTableIII;
  std::vector<PaperComparison> rows;
  const auto add = [&](std::string figure, double paper, double simulated) {
    rows.push_back({std::move(figure), paper, simulated, simulated / paper - 1.0});
  };
  for (int i = 0; i < 3; ++i) {
    add(fmt::format("{}", kResourceNames[i]), T::kShared[i], report.total.shared[i]);
  }
  add("bram_mb", T::kBramMb, report.bram_mib);
  for (int i = 0; i < 4; ++i) {
    add(fmt::format("{}_utilization", kResourceNames[i]), T::kUtilization[i],
        report.utilization[i]);
  }
  for (int i = 0; i < 3; ++i) {
    add(fmt::format("ns_{}", kResourceNames[i]), T::kNs[i], report.total.ns[i]);
  }
  add("ns_bram_mb", T::kNsBramMb, report.ns_bram_mib);
  for (int i = 0; i < 4; ++i) {
    add(fmt::format("frontend_share_{}", kResourceNames[i]), T::kFrontendShare[i],
        report.frontend_share[i]);
  }
  return rows;
}

CostConfig calibrate_control_overheads(const ResourceReport& report, CostConfig cost) {
  using T = EdxCarTableIII;
  const auto datapath = [&](const std::string& group) {
    Resources r;
    for (const CostEntry& e : report.entries) {
      if (e.group == group && e.kind != "control") r += e.shared;
    }
    return r;
  };
  const auto fraction = [](double target, double datapath) {
    return datapath > 0 ? std::max(0.0, target / datapath - 1.0) : 0.0;
  };
  const Resources fe = datapath("frontend"), be = datapath("backend");
  cost.frontend_lut_overhead = fraction(T::kShared.lut * T::kFrontendShare.lut, fe.lut);
  cost.frontend_ff_overhead = fraction(T::kShared.ff * T::kFrontendShare.ff, fe.ff);
  cost.backend_lut_overhead = fraction(T::kShared.lut * (1 - T::kFrontendShare.lut), be.lut);
  cost.backend_ff_overhead = fraction(T::kShared.ff * (1 - T::kFrontendShare.ff), be.ff);
  return cost;
}

}  // namespace edx::arch::cost
