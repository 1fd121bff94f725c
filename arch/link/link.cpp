#include "arch/link/link.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

/// Nanoseconds (double) to the nearest picosecond.
sim::Time ns_to_time(double value_ns) {
  return static_cast<sim::Time>(std::llround(value_ns * 1e3));
}

}  // namespace

const char* to_string(Direction direction) {
  return direction == Direction::HostToFpga ? "host_to_fpga" : "fpga_to_host";
}

const FieldList<LinkConfig>& LinkConfig::fields() {
  using C = LinkConfig;
  static const FieldList<C> list = {
      field("name", &C::name, "", "the link's name in results"),
      field("bandwidth_gb_per_s", &C::bandwidth_gb_per_s, "GB/s",
            "wire bandwidth per direction, 10^9 bytes/s", Bounds::above(0)),
      field("latency_ns", &C::latency_ns, "ns", "one-way latency after a chunk leaves the wire",
            Bounds::at_least(0).below(1e9)),
      field("full_duplex", &C::full_duplex, "",
            "one wire and one DMA engine per direction (PCIe; AXI4 read/write channels)"),
  };
  return list;
}

void LinkConfig::validate() const {
  check_fields(*this, "link", fields());
  require_field(!name.empty(), "link", "name", "a non-empty name");
}

nlohmann::json LinkConfig::to_json() const { return fields_to_json(*this, fields()); }

const FieldList<DmaConfig>& DmaConfig::fields() {
  using C = DmaConfig;
  static const FieldList<C> list = {
      field("setup_ns", &C::setup_ns, "ns",
            "per chunk request (descriptor fetch / issue), overlapped across outstanding requests",
            Bounds::at_least(0).below(1e9)),
      field("chunk_bytes", &C::chunk_bytes, "bytes", "bytes per request",
            Bounds::at_least(1).at_most(1 << 30)),
      field("max_outstanding", &C::max_outstanding, "", "requests in flight per direction",
            Bounds::at_least(1)),
  };
  return list;
}

void DmaConfig::validate() const { check_fields(*this, "link.dma", fields()); }

nlohmann::json DmaConfig::to_json() const { return fields_to_json(*this, fields()); }

void LinkSpec::validate() const {
  link.validate();
  dma.validate();
}

nlohmann::json LinkSpec::to_json() const {
  return {{"link", link.to_json()}, {"dma", dma.to_json()}};
}

LinkSpec LinkSpec::pcie3_x8() {
  LinkSpec s;
  s.link.name = "pcie3_x8";
  s.link.bandwidth_gb_per_s = 7.9;  // paper Sec. VII-A (Edx-Car), max PCIe 3.0 bandwidth
  s.link.latency_ns = 500.0;        // ASSUMPTION: one-way PCIe latency of order 0.5 us
  s.link.full_duplex = true;        // PCIe lanes are dual simplex (PCIe base spec)
  s.dma.setup_ns = 1000.0;          // ASSUMPTION: ~1 us per DMA descriptor/request
  s.dma.chunk_bytes = 4096;         // ASSUMPTION: one 4 KiB page per descriptor
  s.dma.max_outstanding = 8;        // ASSUMPTION: 8 requests in flight per channel
  return s;
}

LinkSpec LinkSpec::axi4() {
  LinkSpec s;
  s.link.name = "axi4";
  s.link.bandwidth_gb_per_s = 1.2;  // paper Sec. VII-A (Edx-Drone), max AXI4 bandwidth
  s.link.latency_ns = 100.0;        // ASSUMPTION: PS DDR access latency of order 100 ns
  s.link.full_duplex = true;        // AXI4 read and write channels are independent (AMBA AXI4)
  s.dma.setup_ns = 200.0;           // ASSUMPTION: burst issue overhead
  s.dma.chunk_bytes = 4096;         // AXI4 bursts may not cross 4 KB (AMBA AXI4 spec)
  s.dma.max_outstanding = 8;        // ASSUMPTION: outstanding transactions of the HP port
  return s;
}

LinkSpec LinkSpec::preset(const std::string& name) {
  if (name == "pcie3_x8") return pcie3_x8();
  if (name == "axi4") return axi4();
  throw std::runtime_error(fmt::format("link.preset: expected pcie3_x8 or axi4, got '{}'", name));
}

const std::vector<std::string>& LinkSpec::preset_names() {
  static const std::vector<std::string> names = {"pcie3_x8", "axi4"};
  return names;
}

std::vector<ReferenceRow> LinkSpec::reference() {
  const LinkSpec defaults;
  std::vector<ReferenceRow> rows = {reference_row(
      "link", "preset", FieldKind::kText, "", std::string(), {}, preset_names(),
      "start from a preset's values (the keys below override them): pcie3_x8 (Edx-Car), axi4 "
      "(Edx-Drone)")};
  for (ReferenceRow& row : reference_rows("link", LinkConfig::fields(), defaults.link)) {
    rows.push_back(std::move(row));
  }
  for (ReferenceRow& row : reference_rows("link.dma", DmaConfig::fields(), defaults.dma)) {
    rows.push_back(std::move(row));
  }
  return rows;
}

LinkSpec LinkSpec::from_yaml(const YAML::Node& node, const std::string& where,
                             const std::string& prefix) {
  YamlFields fields(node, where, prefix);
  LinkSpec s;
  if (const YAML::Node preset_node = fields.take("preset")) {
    const FieldValue name =
        read_field_value(fields, "preset", preset_node, FieldKind::kText, {}, preset_names());
    s = preset(std::get<std::string>(name));
  }
  parse_fields(fields, s.link, LinkConfig::fields());
  fields.finish_except({"dma"});
  validate_at(fields, [&] { s.link.validate(); });

  const YAML::Node dma_node = (node && node.IsMap()) ? node["dma"] : YAML::Node();
  YamlFields dma(dma_node, where, prefix + ".dma");
  parse_fields(dma, s.dma, DmaConfig::fields());
  dma.finish();
  validate_at(dma, [&] { s.dma.validate(); });
  return s;
}

sim::Time wire_time(const LinkConfig& link, std::int64_t bytes) {
  // bytes / (GBps * 1e9) s = bytes * 1000 / GBps ps
  const double picoseconds = static_cast<double>(bytes) * 1e3 / link.bandwidth_gb_per_s;
  // llround is undefined past 2^63; a tiny bandwidth must not wrap into a short time.
  constexpr double kLimitPs = 9223372036854775808.0;  // 2^63
  if (!std::isfinite(picoseconds) || picoseconds < 0.0 || picoseconds >= kLimitPs) {
    throw std::out_of_range(
        fmt::format("link.bandwidth_gb_per_s {}: {} bytes would take {:g} s on the wire, beyond "
                    "the simulated time range (2^63 ps, 107 days)",
                    link.bandwidth_gb_per_s, bytes, picoseconds * 1e-12));
  }
  return static_cast<sim::Time>(std::llround(picoseconds));
}

sim::Time chunk_wire_time(const LinkConfig& link, std::int64_t offset, std::int64_t bytes) {
  return wire_time(link, offset + bytes) - wire_time(link, offset);
}

sim::Time transfer_time(const LinkSpec& spec, std::int64_t bytes) {
  if (bytes < 0) {
    throw std::runtime_error(fmt::format("link transfer: expected bytes >= 0, got {}", bytes));
  }
  if (bytes == 0) return 0;
  const std::int64_t chunk = spec.dma.chunk_bytes;
  const std::int64_t n = (bytes + chunk - 1) / chunk;  // ceil(B / C)
  const auto k = static_cast<std::size_t>(spec.dma.max_outstanding);
  const sim::Time setup = ns_to_time(spec.dma.setup_ns);
  const sim::Time latency = ns_to_time(spec.link.latency_ns);
  // D_j of the last K chunks (chunk j reuses the slot of chunk j - K): a ring of K entries.
  std::vector<sim::Time> done(std::min(k, static_cast<std::size_t>(n)), 0);
  sim::Time wire_end = 0;  // E_{j-1}
  sim::Time last = 0;
  for (std::int64_t j = 0; j < n; ++j) {
    const auto slot = static_cast<std::size_t>(j) % done.size();
    const std::int64_t chunk_bytes = std::min(chunk, bytes - j * chunk);
    const sim::Time start = static_cast<std::size_t>(j) < k ? 0 : done[slot];  // S_j = D_{j-K}
    const sim::Time on_wire = std::max(start + setup, wire_end);  // W_j = max(R_j, E_{j-1})
    wire_end = on_wire + chunk_wire_time(spec.link, j * chunk, chunk_bytes);  // E_j
    last = done[slot] = wire_end + latency;                                   // D_j
  }
  return last;
}

DmaLink::DmaLink(sim::Simulator& sim, LinkSpec spec)
    : sim_(&sim),
      created_(sim.now()),
      spec_((spec.validate(), std::move(spec))),
      setup_(ns_to_time(spec_.dma.setup_ns)),
      latency_(ns_to_time(spec_.link.latency_ns)),
      h2c_(spec_.dma.max_outstanding),
      c2h_(spec_.dma.max_outstanding) {
  // Half duplex: one wire and one DMA engine (its K slots) for both directions.
  h2c_.wire = &h2c_.own_wire;
  c2h_.wire = spec_.link.full_duplex ? &c2h_.own_wire : &h2c_.own_wire;
  h2c_.slot_free = &h2c_.own_slots;
  c2h_.slot_free = spec_.link.full_duplex ? &c2h_.own_slots : &h2c_.own_slots;
}

double DmaLink::wire_utilization(Direction d) const {
  const sim::Time elapsed = sim_->now() - created_;
  return elapsed > 0 ? static_cast<double>(wire_busy_time(d)) / static_cast<double>(elapsed) : 0.0;
}

sim::Task<void> DmaLink::transfer(std::int64_t bytes, Direction direction) {
  co_await transfer(bytes, direction, std::string());
}

sim::Task<void> DmaLink::transfer(std::int64_t bytes, Direction direction, std::string label) {
  if (bytes < 0) {
    throw std::runtime_error(
        fmt::format("link '{}' transfer: expected bytes >= 0, got {}", spec_.link.name, bytes));
  }
  Lane& l = lane(direction);
  const auto later = std::greater<sim::Time>();
  const sim::Time begin = sim_->now();
  sim::Time last_arrival = begin;
  const std::int64_t chunk_size = spec_.dma.chunk_bytes;
  std::vector<sim::Time>& slots = *l.slot_free;
  for (std::int64_t offset = 0; offset < bytes; offset += chunk_size) {
    // Ask for a slot now: the earliest free one (earlier requests took the earlier ones, as a
    // FIFO queue would hand them out); granted at G = max(now, its free time).
    std::pop_heap(slots.begin(), slots.end(), later);
    const sim::Time grant = std::max(sim_->now(), slots.back());
    // Setup, then the wire in grant order (W = max(G + s, wire free)), then the flight; the
    // slot is held until the chunk has arrived.
    const std::int64_t chunk_bytes = std::min(chunk_size, bytes - offset);
    const sim::Time wire_start = std::max(grant + setup_, l.wire->free_at);
    const sim::Time on_wire = chunk_wire_time(spec_.link, offset, chunk_bytes);
    l.wire->free_at = wire_start + on_wire;
    l.wire->busy.add(on_wire);
    const sim::Time arrival = l.wire->free_at + latency_;
    slots.back() = arrival;
    std::push_heap(slots.begin(), slots.end(), later);
    l.chunks.add();
    last_arrival = std::max(last_arrival, arrival);
    // The next chunk's slot is asked for once this one is granted.
    if (grant > sim_->now()) co_await sim_->delay_until(grant);
  }
  if (last_arrival > sim_->now()) co_await sim_->delay_until(last_arrival);
  l.bytes.add(static_cast<std::uint64_t>(bytes));
  l.transfers.add();
  l.latency_us.add(sim::to_us(sim_->now() - begin));
  if (timeline_ != nullptr) {
    timeline_->span(direction == Direction::HostToFpga ? h2c_track_ : c2h_track_,
                    label.empty() ? fmt::format("{} {} B", to_string(direction), bytes)
                                  : fmt::format("{} {} B", label, bytes),
                    begin, sim_->now(), {{"bytes", bytes}});
  }
}

void DmaLink::register_stats(sim::StatsRegistry& registry, const std::string& prefix) const {
  for (const Direction d : {Direction::HostToFpga, Direction::FpgaToHost}) {
    const Lane& l = lane(d);
    const std::string base = prefix + "." + to_string(d);
    registry.add(base + ".bytes", l.bytes);
    registry.add(base + ".transfers", l.transfers);
    registry.add(base + ".chunks", l.chunks);
    registry.add(base + ".latency_us", l.latency_us);
    if (spec_.link.full_duplex) registry.add(base + ".wire_busy_ps", l.wire->busy);
  }
  if (!spec_.link.full_duplex) registry.add(prefix + ".wire_busy_ps", h2c_.own_wire.busy);
}

void DmaLink::set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId track) {
  set_timeline(timeline, track, track);
}

void DmaLink::set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId host_to_fpga,
                           sim::Timeline::TrackId fpga_to_host) {
  timeline_ = &timeline;
  h2c_track_ = host_to_fpga;
  c2h_track_ = fpga_to_host;
}

}  // namespace edx::arch
