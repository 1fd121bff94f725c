#pragma once
// Host <-> FPGA links and their DMA engines (paper Sec. VII-A; docs/MODEL.md, "Links").
//
// A transfer of B bytes is split into n = ceil(B / C) chunks of C bytes (the last one shorter).
// Each chunk holds one of K request slots (max_outstanding) from the start of its setup until it
// has arrived; it spends s (setup_ns: descriptor fetch / request issue, overlapped across the K
// slots), then occupies the wire for w_j = bytes_j / bandwidth (serialized: one chunk on the wire
// at a time, per direction on a full-duplex link), then L (latency_ns) to arrive. For an idle
// link (transfer_time()):
//   S_j = 0 for j < K, else D_{j-K}     (slot freed by chunk j - K)
//   R_j = S_j + s                        (ready for the wire)
//   W_j = max(R_j, E_{j-1}),  E_j = W_j + w_j,  D_j = E_j + L,  T = D_{n-1}
// When the slots never limit (K * w >= s + w + L, w a full chunk's wire time) this is
// T = s + sum_j w_j + L = s + B / bandwidth + L. The DES (DmaLink::transfer) runs the same model
// with concurrent transfers contending for the slots and the wire: slots are granted first come,
// first served (a transfer asks for its next chunk's slot once the previous chunk has one), and
// because every chunk spends the same setup s before the wire, chunks reach the wire in the order
// their slots were granted. So when a slot is granted at G, the chunk's wire start
// W = max(G + s, wire free), its arrival D = W + w + L and the slot's next free time are already
// determined: the DES books them then, with no process per chunk; a transfer waits only for
// its grants and its last arrival (tests/arch/link: the same schedule as a process per chunk).
// A half-duplex link has one wire and one DMA engine (one set of K slots) for both directions.
//
// Bandwidths in GB/s are decimal (10^9 bytes/s). Wire times are whole picoseconds: the chunk at
// byte offset o of a transfer, of b bytes, takes w = wire(o + b) - wire(o) with
// wire(x) = round(x * 1000 / bandwidth_GB_per_s) ps, so a transfer's chunks add up to exactly
// wire(B) (no per-chunk rounding drift).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/config_fields.hpp"
#include "sim_core/engine.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

/// Which way the bytes go.
enum class Direction { HostToFpga, FpgaToHost };
/// "host_to_fpga" / "fpga_to_host".
const char* to_string(Direction direction);

/// The physical link.
struct LinkConfig {
  std::string name = "pcie3_x8";
  double bandwidth_gb_per_s = 7.9;  ///< 10^9 bytes per second
  double latency_ns = 500.0;        ///< one-way, after a chunk leaves the wire
  bool full_duplex = true;          ///< one wire per direction (PCIe, AXI4 read/write channels)
  /// Every key of `link:` but `preset` and `dma` (docs/CONFIG.md).
  static const FieldList<LinkConfig>& fields();
  /// Throws std::runtime_error naming the bad field: "link.bandwidth_gb_per_s: expected ...".
  void validate() const;
  nlohmann::json to_json() const;
};

/// The DMA engine driving it (one per direction).
struct DmaConfig {
  double setup_ns = 1000.0;         ///< per chunk request, overlapped across outstanding requests
  std::int64_t chunk_bytes = 4096;  ///< bytes per request
  int max_outstanding = 8;          ///< requests in flight per direction
  /// Every key of `link.dma:` (docs/CONFIG.md).
  static const FieldList<DmaConfig>& fields();
  /// Throws std::runtime_error naming the bad field: "dma.chunk_bytes: expected ...".
  void validate() const;
  nlohmann::json to_json() const;
};

/// A link with its DMA engine, as configured in a platform file.
struct LinkSpec {
  LinkConfig link;
  DmaConfig dma;
  void validate() const;
  nlohmann::json to_json() const;

  /// PCIe 3.0 x8 of Edx-Car: 7.9 GB/s (paper Sec. VII-A; 8 GT/s x 8 lanes x 128/130 = 7.88 GB/s,
  /// PCIe 3.0 base spec). Latency, setup, chunk and outstanding count are assumptions (see
  /// link.cpp).
  static LinkSpec pcie3_x8();
  /// AXI4 of Edx-Drone (PL reading PS DRAM): 1.2 GB/s (paper Sec. VII-A). Latency, setup, chunk
  /// and outstanding count are assumptions (see link.cpp).
  static LinkSpec axi4();
  /// "pcie3_x8" or "axi4"; throws std::runtime_error otherwise.
  static LinkSpec preset(const std::string& name);
  static const std::vector<std::string>& preset_names();
  /// Every key of `link:` (preset, the link, `dma:`), defaults from pcie3_x8 (docs/CONFIG.md).
  static std::vector<ReferenceRow> reference();
  /// Reads a `link:` map over the defaults: optional `preset: pcie3_x8|axi4` first, then
  /// `name`, `bandwidth_gb_per_s`, `latency_ns`, `full_duplex`, and a `dma:` map with
  /// `setup_ns`, `chunk_bytes`, `max_outstanding`. Errors name file, line and key; unknown keys
  /// are errors. `prefix` is the dotted path of the map (e.g. "link").
  static LinkSpec from_yaml(const YAML::Node& node, const std::string& where,
                            const std::string& prefix = "link");
};

/// Wire time of `bytes` on `link`: round(bytes * 1000 / bandwidth_GB_per_s) ps; throws
/// std::out_of_range naming `link.bandwidth_gb_per_s` when that is 2^63 ps or more.
sim::Time wire_time(const LinkConfig& link, std::int64_t bytes);
/// Wire time of the chunk of `bytes` at byte `offset` of a transfer:
/// wire_time(offset + bytes) - wire_time(offset).
sim::Time chunk_wire_time(const LinkConfig& link, std::int64_t offset, std::int64_t bytes);

/// Time of one `bytes` transfer on an idle link (the recurrence at the top of link.hpp); 0 for
/// 0 bytes. `spec` validated (at load, or by DmaLink). Throws std::runtime_error for negative
/// bytes.
sim::Time transfer_time(const LinkSpec& spec, std::int64_t bytes);

/// The DES model of a link and its DMA engines on a Simulator. Must be destroyed before it.
///
///   DmaLink link(sim, LinkSpec::pcie3_x8());
///   co_await link.transfer(2048, Direction::FpgaToHost);
class DmaLink {
 public:
  DmaLink(sim::Simulator& sim, LinkSpec spec);
  DmaLink(const DmaLink&) = delete;
  DmaLink& operator=(const DmaLink&) = delete;

  /// Moves `bytes` in `direction`; completes when the last chunk has arrived. Concurrent
  /// transfers share the direction's request slots (FIFO) and the wire.
  sim::Task<void> transfer(std::int64_t bytes, Direction direction);

  /// Idle-link time of a transfer (free function transfer_time() with this link's spec).
  sim::Time transfer_time(std::int64_t bytes) const { return arch::transfer_time(spec_, bytes); }

  /// Registers, per direction d: <prefix>.<d>.bytes, .transfers, .chunks (counters),
  /// .latency_us (per-transfer time, samples) and .wire_busy_ps (counter: time the wire carried
  /// its chunks; shared by both directions on a half-duplex link: then <prefix>.wire_busy_ps).
  void register_stats(sim::StatsRegistry& registry, const std::string& prefix) const;

  /// Records each transfer as a span on `track` of `timeline` (optional).
  void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId track);
  /// The same with one track per direction.
  void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId host_to_fpga,
                    sim::Timeline::TrackId fpga_to_host);
  /// As transfer(); `label` prefixes its timeline span (e.g. "f12 kalman_gain in").
  sim::Task<void> transfer(std::int64_t bytes, Direction direction, std::string label);

  const LinkSpec& spec() const noexcept { return spec_; }
  std::uint64_t bytes(Direction d) const noexcept { return lane(d).bytes.value(); }
  std::uint64_t transfers(Direction d) const noexcept { return lane(d).transfers.value(); }
  std::uint64_t chunks(Direction d) const noexcept { return lane(d).chunks.value(); }
  const sim::SampleSet& latency_us(Direction d) const noexcept { return lane(d).latency_us; }
  /// Time the wire of direction `d` carried chunks, booked so far (on a half-duplex link both
  /// directions' chunks, on the one wire).
  sim::Time wire_busy_time(Direction d) const noexcept { return lane(d).wire->busy.value(); }
  /// wire_busy_time over the time from the link's creation to now (0 before any time passed).
  double wire_utilization(Direction d) const;

 private:
  /// A wire: when it is next free and how long it has carried chunks.
  struct Wire {
    sim::Time free_at = 0;
    sim::Counter busy;  ///< ps
  };
  struct Lane {
    explicit Lane(int slot_count) : own_slots(static_cast<std::size_t>(slot_count), 0) {}
    std::vector<sim::Time> own_slots;             ///< min-heap: when each request slot is next free
    std::vector<sim::Time>* slot_free = nullptr;  ///< own_slots, or the shared ones
    Wire own_wire;
    Wire* wire = nullptr;
    sim::Counter bytes, transfers, chunks;
    sim::SampleSet latency_us;
  };

  const Lane& lane(Direction d) const noexcept { return d == Direction::HostToFpga ? h2c_ : c2h_; }
  Lane& lane(Direction d) noexcept { return d == Direction::HostToFpga ? h2c_ : c2h_; }

  sim::Simulator* sim_;
  sim::Time created_;
  LinkSpec spec_;
  sim::Time setup_;
  sim::Time latency_;
  Lane h2c_;
  Lane c2h_;
  sim::Timeline* timeline_ = nullptr;
  sim::Timeline::TrackId h2c_track_{}, c2h_track_{};
};

}  // namespace edx::arch
