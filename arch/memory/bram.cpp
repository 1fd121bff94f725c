#include "arch/memory/bram.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "arch/memory/on_chip_memory.hpp"

namespace edx::arch {
namespace {

std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

nlohmann::json aspect_json(const BramAspect& a) {
  return {{"primitive", a.half ? "BRAM18" : "BRAM36"},
          {"width_bits", a.width_bits},
          {"depth_words", a.depth_words},
          {"simple_dual_port", a.simple_dual_port_only}};
}

}  // namespace

double bytes_of_blocks(double blocks, bool include_parity) {
  return blocks * static_cast<double>(include_parity ? kBram36BytesWithParity : kBram36DataBytes);
}

double to_mib(double bytes) { return bytes / (1024.0 * 1024.0); }

void MemoryStructure::validate() const {
  if (name.empty()) throw std::runtime_error("memory structure: expected a non-empty name");
  if (width_bits < 0) {
    throw std::runtime_error(
        fmt::format("memory structure '{}': width_bits: expected >= 0, got {}", name, width_bits));
  }
  if (depth_words < 0) {
    throw std::runtime_error(fmt::format(
        "memory structure '{}': depth_words: expected >= 0, got {}", name, depth_words));
  }
  if (count < 0) {
    throw std::runtime_error(
        fmt::format("memory structure '{}': count: expected >= 0, got {}", name, count));
  }
}

nlohmann::json MemoryStructure::to_json() const {
  return {
      {"name", name}, {"width_bits", width_bits}, {"depth_words", depth_words}, {"count", count}};
}

nlohmann::json BramMapping::to_json() const {
  return {
      {"aspect", aspect_json(aspect)}, {"columns", columns}, {"rows", rows}, {"blocks", blocks}};
}

BramMapping map_to_bram(std::int64_t width_bits, std::int64_t depth_words, bool allow_bram18) {
  if (width_bits < 0 || depth_words < 0) {
    throw std::runtime_error(
        fmt::format("BRAM mapping: expected width_bits >= 0 and depth_words >= 0, got {} x {}",
                    width_bits, depth_words));
  }
  BramMapping best;
  if (width_bits == 0 || depth_words == 0) {
    best.aspect = kBram36Aspects.front();
    return best;  // nothing to store
  }
  bool found = false;
  auto consider = [&](const BramAspect& aspect) {
    BramMapping m;
    m.aspect = aspect;
    m.columns = ceil_div(width_bits, aspect.width_bits);  // ceil(W / w)
    m.rows = ceil_div(depth_words, aspect.depth_words);   // ceil(D / d)
    m.blocks = static_cast<double>(m.columns * m.rows) * (aspect.half ? 0.5 : 1.0);
    if (!found || m.blocks < best.blocks) {
      best = m;
      found = true;
    }
  };
  for (const BramAspect& a : kBram36Aspects) consider(a);
  if (allow_bram18) {
    for (const BramAspect& a : kBram18Aspects) consider(a);
  }
  return best;
}

Device Device::xc7v690t() {
  return {
      "XC7V690T", 1470,
      433200,     866400,
      3600,       "Xilinx DS180 (7 Series FPGAs Data Sheet: Overview), Virtex-7 feature summary"};
}

Device Device::zu9eg() {
  return {"ZU9EG",
          912,
          274080,
          548160,
          2520,
          "Xilinx DS891 (Zynq UltraScale+ MPSoC Data Sheet: Overview), feature summary; ZU9CG "
          "has the same programmable logic"};
}

std::optional<Device> Device::find(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "xc7v690t") return xc7v690t();
  if (lower == "zu9eg" || lower == "zu9cg") {
    Device d = zu9eg();
    if (lower == "zu9cg") d.name = "ZU9CG";
    return d;
  }
  return std::nullopt;
}

const char* Device::known_names() { return "xc7v690t, zu9eg or zu9cg"; }

Device Device::by_name(const std::string& name) {
  if (std::optional<Device> device = find(name)) return *device;
  throw std::runtime_error(
      fmt::format("device: unknown device '{}' (expected {})", name, known_names()));
}

nlohmann::json Device::to_json() const {
  return {{"name", name}, {"bram36_blocks", bram36_blocks},
          {"luts", luts}, {"flip_flops", flip_flops},
          {"dsps", dsps}, {"source", source}};
}

double BramBudget::total_bytes(bool include_parity) const {
  return bytes_of_blocks(total_blocks, include_parity);
}

nlohmann::json BramBudget::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const StructureUsage& u : structures) {
    list.push_back({{"structure", u.structure.to_json()},
                    {"mapping", u.mapping.to_json()},
                    {"blocks", u.blocks}});
  }
  return {{"list", list_name},
          {"device", device_name},
          {"structures", list},
          {"total_blocks", total_blocks},
          {"device_blocks", device_blocks},
          {"utilization", utilization},
          {"total_bytes_with_parity", total_bytes(true)},
          {"total_data_bytes", total_bytes(false)},
          {"fits", fits},
          {"message", message}};
}

BramBudget check_bram(const std::string& list_name, const std::vector<MemoryStructure>& structures,
                      const Device& device, const OnChipMemory& memory) {
  if (device.bram36_blocks <= 0) {
    throw std::runtime_error(fmt::format("device '{}': bram36_blocks: expected > 0, got {}",
                                         device.name, device.bram36_blocks));
  }
  BramBudget budget;
  budget.list_name = list_name;
  budget.device_name = device.name;
  budget.device_blocks = device.bram36_blocks;
  for (const MemoryStructure& s : structures) {
    s.validate();
    StructureUsage usage;
    usage.structure = s;
    usage.mapping = memory.mapping(s);
    usage.blocks = memory.cost(s).bram;
    budget.total_blocks += usage.blocks;
    budget.structures.push_back(usage);
  }
  budget.utilization = budget.total_blocks / static_cast<double>(device.bram36_blocks);
  budget.fits = budget.total_blocks <= static_cast<double>(device.bram36_blocks);
  if (!budget.fits) {
    budget.message = fmt::format(
        "BRAM: structures '{}' need {} BRAM36 blocks but device {} has {} ({:.1f} % used)",
        list_name, budget.total_blocks, device.name, device.bram36_blocks,
        100.0 * budget.utilization);
  }
  return budget;
}

}  // namespace edx::arch
