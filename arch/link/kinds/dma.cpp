// The link kind `dma` (paper Sec. VII-A; docs/MODEL.md, "Links"): a wire of a given bandwidth
// and latency driven by a DMA engine that moves a transfer in chunks.
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
// T = s + sum_j w_j + L = s + B / bandwidth + L. The DES (DmaModel::transfer) runs the same model
// with concurrent transfers contending for the slots and the wire: slots are granted first come,
// first served (a transfer asks for its next chunk's slot once the previous chunk has one), and
// because every chunk spends the same setup s before the wire, chunks reach the wire in the order
// their slots were granted. So when a slot is granted at G, the chunk's wire start
// W = max(G + s, wire free), its arrival D = W + w + L and the slot's next free time are already
// determined: the DES books them then, with no process per chunk; a transfer waits only for
// its grants and its last arrival (tests/arch/link: the same schedule as a process per chunk).
// A transfer that starts on an idle link and ends before anything else can happen is booked
// whole in the closed form above (book_idle: no chunk loop, no event).
// A half-duplex link has one wire and one DMA engine (one set of K slots) for both directions.
//
// Bandwidths in GB/s are decimal (10^9 bytes/s). Wire times are whole picoseconds: the chunk at
// byte offset o of a transfer, of b bytes, takes w = wire(o + b) - wire(o) with
// wire(x) = round(x * 1000 / bandwidth_GB_per_s) ps, so a transfer's chunks add up to exactly
// wire(B) (no per-chunk rounding drift).
//
//   link: {kind: dma, preset: axi4, bandwidth_gb_per_s: 2.4, dma: {chunk_bytes: 2048}}
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "arch/common/bounds.hpp"
#include "arch/link/link.hpp"

namespace edx::arch {
namespace {

/// std::llround(x) for 0 <= x < 2^63, inline (the library call was a tenth of the link's DES):
/// i = trunc(x), then up when x - i >= 1/2. x - i is exact (x < 1: i = 0; x >= 1: i >= x / 2,
/// Sterbenz; x >= 2^52: x is whole and x - i = 0), so halves go away from zero as llround's do.
std::int64_t round_nonnegative(double x) {
  const auto i = static_cast<std::int64_t>(x);
  return x - static_cast<double>(i) >= 0.5 ? i + 1 : i;
}

/// Nanoseconds (double) to the nearest picosecond.
sim::Time ns_to_time(double value_ns) {
  return static_cast<sim::Time>(std::llround(value_ns * 1e3));
}

/// The DMA engine driving the wire (one per direction on a full-duplex link).
struct DmaEngine {
  double setup_ns = 1000.0;         ///< per chunk request, overlapped across outstanding requests
  std::int64_t chunk_bytes = 4096;  ///< bytes per request
  int max_outstanding = 8;          ///< requests in flight per direction
  static const FieldList<DmaEngine>& fields() {
    using C = DmaEngine;
    static const FieldList<C> list = {
        field("setup_ns", &C::setup_ns, "ns",
              "per chunk request (descriptor fetch / issue), overlapped across outstanding "
              "requests",
              Bounds::at_least(0).below(1e9)),
        field("chunk_bytes", &C::chunk_bytes, "bytes", "bytes per request",
              Bounds::at_least(1).at_most(1 << 30)),
        // PCIe's 10-bit tags allow at most 1024 non-posted requests in flight (PCIe 4.0).
        field("max_outstanding", &C::max_outstanding, "", "requests in flight per direction",
              Bounds::at_least(1).at_most(1024)),
    };
    return list;
  }
};

class DmaLink final : public Link {
 public:
  struct Params {
    std::string name = "pcie3_x8";
    double bandwidth_gb_per_s = 7.9;  ///< 10^9 bytes per second
    double latency_ns = 500.0;        ///< one-way, after a chunk leaves the wire
    bool full_duplex = true;          ///< one wire per direction (PCIe, AXI4 read/write channels)
    /// ASSUMPTION: 10 pJ/bit for a PCIe 3.0 SerDes + controller; no preset changes it.
    double pj_per_byte = 80.0;
    DmaEngine dma;  ///< `dma:`

    /// PCIe 3.0 x8 of Edx-Car (the defaults): 7.9 GB/s (paper Sec. VII-A; 8 GT/s x 8 lanes x
    /// 128/130 = 7.88 GB/s, PCIe 3.0 base spec); the rest assumed.
    static Params pcie3_x8() { return Params{}; }
    /// AXI4 of Edx-Drone (PL reading PS DRAM): 1.2 GB/s (paper Sec. VII-A); the rest assumed.
    static Params axi4() {
      Params p;
      p.name = "axi4";
      p.bandwidth_gb_per_s = 1.2;  // paper Sec. VII-A (Edx-Drone), max AXI4 bandwidth
      p.latency_ns = 100.0;        // ASSUMPTION: PS DDR access latency of order 100 ns
      p.full_duplex = true;        // AXI4 read and write channels are independent (AMBA AXI4)
      p.dma.setup_ns = 200.0;      // ASSUMPTION: burst issue overhead
      p.dma.chunk_bytes = 4096;    // AXI4 bursts may not cross 4 KB (AMBA AXI4 spec)
      p.dma.max_outstanding = 8;   // ASSUMPTION: outstanding transactions of the HP port
      return p;
    }
    // pcie3_x8's assumptions: one-way latency of order 0.5 us, ~1 us per DMA descriptor, one
    // 4 KiB page per descriptor, 8 requests in flight per channel; PCIe lanes are dual simplex.

    static const std::vector<std::string>& preset_names() {
      static const std::vector<std::string> names = {"pcie3_x8", "axi4"};
      return names;
    }

    /// The keys of the link itself (`preset` and `dma:` are read by parse()).
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("name", &C::name, "", "the link's name in results"),
          // At least 100 B/s: a chunk of the largest size (2^30 B) then takes at most 1.1e7 s,
          // inside simulated time (2^63 ps); a transfer too long for it is refused by wire_time.
          field("bandwidth_gb_per_s", &C::bandwidth_gb_per_s, "GB/s",
                "wire bandwidth per direction, 10^9 bytes/s", Bounds::at_least(1e-7)),
          field("latency_ns", &C::latency_ns, "ns", "one-way latency after a chunk leaves the wire",
                Bounds::at_least(0).below(1e9)),
          field("full_duplex", &C::full_duplex, "",
                "one wire and one DMA engine per direction (PCIe; AXI4 read/write channels)"),
          field("pj_per_byte", &C::pj_per_byte, "pJ/byte",
                "energy of a byte crossing the link (assumed 10 pJ/bit)", bounds::energy_pj()),
      };
      return list;
    }

    /// wire(x) = round(x * 1000 / bandwidth_GB_per_s) ps; throws std::out_of_range naming
    /// link.bandwidth_gb_per_s when that is 2^63 ps or more.
    sim::Time wire_time(std::int64_t bytes) const {
      // bytes / (GBps * 1e9) s = bytes * 1000 / GBps ps
      const double picoseconds = static_cast<double>(bytes) * 1e3 / bandwidth_gb_per_s;
      // llround is undefined past 2^63; a tiny bandwidth must not wrap into a short time. The
      // test is false for NaN and infinities too (isfinite and the range in one); the error is
      // built out of line, so this inlines into the chunk loops.
      if (!(picoseconds >= 0.0 && picoseconds < kLimitPs)) [[unlikely]] {
        throw_wire_range(bytes, picoseconds);
      }
      return static_cast<sim::Time>(round_nonnegative(picoseconds));
    }
    /// wire_time's error: link.bandwidth_gb_per_s named, the transfer's seconds.
    [[noreturn]] [[gnu::noinline]] void throw_wire_range(std::int64_t bytes,
                                                         double picoseconds) const {
      throw std::out_of_range(
          fmt::format("link.bandwidth_gb_per_s {}: {} bytes would take {:g} s on the wire, beyond "
                      "the simulated time range (2^63 ps, 107 days)",
                      bandwidth_gb_per_s, bytes, picoseconds * 1e-12));
    }
    static constexpr double kLimitPs = 9223372036854775808.0;  ///< 2^63
    /// True when wire_time(bytes) does not throw (wire time monotone in bytes: then no smaller
    /// count throws either).
    bool wire_in_range(std::int64_t bytes) const {
      const double picoseconds = static_cast<double>(bytes) * 1e3 / bandwidth_gb_per_s;
      return picoseconds >= 0.0 && picoseconds < kLimitPs;  // as wire_time (false for NaN, inf)
    }
    /// The chunk of `bytes` at byte `offset` of a transfer: wire(offset + bytes) - wire(offset).
    sim::Time chunk_wire_time(std::int64_t offset, std::int64_t bytes) const {
      return wire_time(offset + bytes) - wire_time(offset);
    }

    void validate() const {
      check_fields(*this, "link", fields());
      require_field(!name.empty(), "link", "name", "a non-empty name");
      check_fields(dma, "link.dma", DmaEngine::fields());
    }

    /// `preset:` first (its values are the defaults of the keys that follow), then the link's
    /// keys, then the `dma:` map; unknown keys refused at their line.
    static Params parse(YamlFields& yaml) {
      Params p;
      if (const YAML::Node preset = yaml.take("preset")) {
        const FieldValue name =
            read_field_value(yaml, "preset", preset, FieldKind::kText, {}, preset_names());
        p = std::get<std::string>(name) == "axi4" ? axi4() : pcie3_x8();
      }
      parse_fields(yaml, p, fields());
      YamlFields dma(yaml.take("dma"), yaml.where(), yaml.prefix() + ".dma");
      parse_fields(dma, p.dma, DmaEngine::fields());
      dma.finish();
      return p;
    }

    /// `preset`, the link's keys and `dma.*`, defaults from pcie3_x8.
    static std::vector<ReferenceRow> reference(const std::string& section,
                                               const std::string& title) {
      std::vector<ReferenceRow> rows = {reference_row(
          section, "preset", FieldKind::kText, "", std::string(), {}, preset_names(),
          "start from a preset's values (the keys below override them): pcie3_x8 (Edx-Car, the "
          "defaults), axi4 (Edx-Drone)")};
      rows.back().group = title;
      for (ReferenceRow& row : reference_rows(section, fields(), Params{}, title)) {
        rows.push_back(std::move(row));
      }
      for (ReferenceRow& row :
           reference_rows(section + ".dma", DmaEngine::fields(), DmaEngine{}, title)) {
        rows.push_back(std::move(row));
      }
      return rows;
    }
  };

  explicit DmaLink(const Params& params)
      : params_(params),
        setup_(ns_to_time(params.dma.setup_ns)),
        latency_(ns_to_time(params.latency_ns)),
        slots_never_wait_(slots_never_wait(params, setup_, latency_)) {}

  std::string_view kind() const override { return "dma"; }
  nlohmann::json params_json() const override {
    nlohmann::json j = params_to_json(params_);
    j["dma"] = fields_to_json(params_.dma, DmaEngine::fields());
    return j;
  }
  bool full_duplex() const override { return params_.full_duplex; }
  double pj_per_byte() const override { return params_.pj_per_byte; }

  /// The recurrence at the top of this file.
  sim::Time transfer_time(std::int64_t bytes) const override {
    if (bytes < 0) {
      throw std::runtime_error(fmt::format("link transfer: expected bytes >= 0, got {}", bytes));
    }
    if (bytes == 0) return 0;
    const std::int64_t chunk = params_.dma.chunk_bytes;
    const std::int64_t n = (bytes + chunk - 1) / chunk;  // ceil(B / C)
    const auto k = static_cast<std::size_t>(params_.dma.max_outstanding);
    const sim::Time setup = setup_, latency = latency_;
    // When no chunk waits for a slot (no more chunks than slots, or slots_never_wait_), each
    // reaches the wire when the previous leaves it and the chunks' wire times add up to wire(B)
    // exactly: T = s + wire(B) + L, the loop's figure to the picosecond.
    if (slots_never_wait_ || static_cast<std::size_t>(n) <= k) {
      return setup + params_.wire_time(bytes) + latency;
    }
    // D_j of the last K chunks (chunk j reuses the slot of chunk j - K): a ring of K entries
    // (on the stack for the usual few slots: this runs for every transfer of every frame).
    const std::size_t slots = std::min(k, static_cast<std::size_t>(n));
    std::array<sim::Time, 16> few{};
    std::vector<sim::Time> many(slots > few.size() ? slots : 0, 0);
    sim::Time* const done = slots > few.size() ? many.data() : few.data();
    sim::Time wire_end = 0;  // E_{j-1}
    sim::Time last = 0;
    for (std::int64_t j = 0; j < n; ++j) {
      const auto slot = static_cast<std::size_t>(j) % slots;
      const std::int64_t chunk_bytes = std::min(chunk, bytes - j * chunk);
      const sim::Time start = static_cast<std::size_t>(j) < k ? 0 : done[slot];  // S_j = D_{j-K}
      const sim::Time on_wire = std::max(start + setup, wire_end);  // W_j = max(R_j, E_{j-1})
      wire_end = on_wire + params_.chunk_wire_time(j * chunk, chunk_bytes);  // E_j
      last = done[slot] = wire_end + latency;                                // D_j
    }
    return last;
  }

  std::unique_ptr<LinkModel> make_model(sim::Simulator& sim) const override;

  const Params& params() const { return params_; }

  /// True when chunk j's slot (freed at D_{j-K} = E_{j-K} + L) is always free before the wire
  /// is: E_{j-K} + L + s <= E_{j-1}, i.e. the K - 1 full chunks between them take at least
  /// L + s on the wire. A full chunk's rounded wire time is at least C / bandwidth - 1 ps, so
  /// (K - 1) (C / bandwidth - 1 ps) > L + s (+ 1 ps of margin) suffices (Edx-Car's PCIe: 7 x 517 ns
  /// > 1.5 us).
  static bool slots_never_wait(const Params& p, sim::Time setup, sim::Time latency) {
    const double chunk_ps = static_cast<double>(p.dma.chunk_bytes) * 1e3 / p.bandwidth_gb_per_s;
    return (p.dma.max_outstanding - 1) * (chunk_ps - 1.0) >
           static_cast<double>(latency + setup + 1);
  }

 private:
  Params params_;
  sim::Time setup_;        ///< dma.setup_ns as simulated time
  sim::Time latency_;      ///< latency_ns as simulated time
  bool slots_never_wait_;  ///< see slots_never_wait()
};

/// DmaLink's DES model: the slots and wires of both directions, booked chunk by chunk.
class DmaModel final : public LinkModel {
 public:
  DmaModel(sim::Simulator& sim, const DmaLink& link)
      : sim_(&sim),
        created_(sim.now()),
        params_(link.params()),
        setup_(ns_to_time(params_.dma.setup_ns)),
        latency_(ns_to_time(params_.latency_ns)),
        slots_never_wait_(DmaLink::slots_never_wait(params_, setup_, latency_)),
        h2c_(params_.dma.max_outstanding),
        c2h_(params_.dma.max_outstanding) {
    // Half duplex: one wire and one DMA engine (its K slots) for both directions.
    const bool duplex = params_.full_duplex;
    h2c_.wire = &h2c_.own_wire;
    c2h_.wire = duplex ? &c2h_.own_wire : &h2c_.own_wire;
    h2c_.slot_free = &h2c_.own_slots;
    c2h_.slot_free = duplex ? &c2h_.own_slots : &h2c_.own_slots;
  }
  DmaModel(const DmaModel&) = delete;
  DmaModel& operator=(const DmaModel&) = delete;

  using LinkModel::set_timeline;
  using LinkModel::transfer;

  sim::Task<void> transfer(std::int64_t bytes, Direction direction, std::string label) override {
    if (bytes < 0) {
      throw std::runtime_error(
          fmt::format("link '{}' transfer: expected bytes >= 0, got {}", params_.name, bytes));
    }
    Lane& l = lane(direction);
    const auto later = std::greater<sim::Time>();
    const sim::Time begin = sim_->now();
    sim::Time last_arrival = begin;
    const std::int64_t chunk_size = params_.dma.chunk_bytes;
    const std::int64_t n = (bytes + chunk_size - 1) / chunk_size;  // chunks
    std::vector<sim::Time>& slots = *l.slot_free;
    const auto k = static_cast<std::int64_t>(slots.size());
    if (const std::optional<sim::Time> end = book_idle(l, n, bytes)) {
      // Nothing else is due before the end: the clock moves there without an event.
      if (*end > begin) co_await sim_->advance(*end - begin);
      finish(l, direction, bytes, begin, label);
      co_return;
    }
    // The transfer's time t: now, or a grant it went on to without an event because nothing
    // else can happen until the horizon (Simulator::quiet_horizon: a long transfer alone on the
    // link books its chunks in one event instead of one per slot it waits for).
    Run run{begin, 0, last_arrival};
    sim::Time horizon = sim_->quiet_horizon();
    std::int64_t next_try = k;  // when to try a steady stretch (book_steady) next
    for (std::int64_t j = 0; j < n;) {
      if (j >= next_try && slots_never_wait_) {
        const std::int64_t booked = book_steady(l, j, n, bytes, horizon, run);
        j += booked;
        if (booked == 0) next_try = j + k;  // not now: again after k chunks
        continue;
      }
      const std::int64_t offset = j * chunk_size;
      // Ask for a slot now: the earliest free one (earlier requests took the earlier ones, as a
      // FIFO queue would hand them out); granted at G = max(now, its free time).
      std::pop_heap(slots.begin(), slots.end(), later);
      const sim::Time grant = std::max(run.t, slots.back());
      // Setup, then the wire in grant order (W = max(G + s, wire free)), then the flight; the
      // slot is held until the chunk has arrived.
      const std::int64_t chunk_bytes = std::min(chunk_size, bytes - offset);
      const sim::Time wire_start = std::max(grant + setup_, l.wire->free_at);
      const sim::Time wire_end = params_.wire_time(offset + chunk_bytes);
      const sim::Time on_wire = wire_end - run.wire_done;  // chunk_wire_time(offset, chunk_bytes)
      run.wire_done = wire_end;
      l.wire->free_at = wire_start + on_wire;
      l.wire->busy.add(on_wire);
      const sim::Time arrival = l.wire->free_at + latency_;
      slots.back() = arrival;
      std::push_heap(slots.begin(), slots.end(), later);
      l.chunks.add();
      run.last_arrival = std::max(run.last_arrival, arrival);
      ++j;
      // The next chunk's slot is asked for once this one is granted.
      if (grant > run.t) {
        if (grant > horizon) {
          co_await sim_->delay_until(grant);
          horizon = sim_->quiet_horizon();
        }
        run.t = grant;
      }
    }
    last_arrival = run.last_arrival;
    // At the last arrival, or at t when the transfer went on past now without waiting.
    const sim::Time end = std::max(last_arrival, run.t);
    if (end > sim_->now()) co_await sim_->delay_until(end);
    finish(l, direction, bytes, begin, label);
  }

  /// Per direction d: <prefix>.<d>.bytes, .transfers, .chunks (counters), .latency_us
  /// (per-transfer time, samples) and .wire_busy_ps (counter: time the wire carried its chunks;
  /// on a half-duplex link the one wire's, as <prefix>.wire_busy_ps).
  void register_stats(sim::StatsRegistry& registry, const std::string& prefix) const override {
    const bool duplex = params_.full_duplex;
    for (const Direction d : {Direction::HostToFpga, Direction::FpgaToHost}) {
      const Lane& l = lane(d);
      const std::string base = prefix + "." + to_string(d);
      registry.add(base + ".bytes", l.bytes);
      registry.add(base + ".transfers", l.transfers);
      registry.add(base + ".chunks", l.chunks);
      registry.add(base + ".latency_us", l.latency_us);
      if (duplex) registry.add(base + ".wire_busy_ps", l.wire->busy);
    }
    if (!duplex) registry.add(prefix + ".wire_busy_ps", h2c_.own_wire.busy);
  }

  void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId host_to_fpga,
                    sim::Timeline::TrackId fpga_to_host) override {
    timeline_ = &timeline;
    h2c_track_ = host_to_fpga;
    c2h_track_ = fpga_to_host;
  }

  /// The wire's busy time over the time since the model's creation.
  double wire_utilization(Direction d) const override {
    const sim::Time elapsed = sim_->now() - created_;
    return elapsed > 0
               ? static_cast<double>(lane(d).wire->busy.value()) / static_cast<double>(elapsed)
               : 0.0;
  }

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

  /// A transfer's state between chunks.
  struct Run {
    sim::Time t;             ///< its time: now, or the last grant it went on to
    sim::Time wire_done;     ///< wire(offset of its next chunk)
    sim::Time last_arrival;  ///< its latest chunk arrival so far
  };

  /// A transfer's stats and timeline span, at its end.
  void finish(Lane& l, Direction direction, std::int64_t bytes, sim::Time begin,
              const std::string& label) {
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

  /// Books a whole transfer of `bytes` (n >= 1 chunks) at once when it starts on an idle link
  /// (the wire and every slot free by now t) and ends before anything else can happen
  /// (Simulator::quiet_horizon), as the chunk loop would; returns its end, or nothing when it
  /// does not (the loop books it). The first K chunks are granted at t, chunk j >= K when chunk
  /// j - K arrives, and each finds the wire busy past its setup (chunk 0 excepted: the wire
  /// waits for it): the first K because the wire is busy from t + s on, the later ones by
  /// slots_never_wait (or there are none: n <= K). So chunk j leaves the wire at
  ///   E_j = t + s + wire(end_j)   (telescoping the chunks' wire(end) - wire(offset))
  /// and arrives at A_j = E_j + L; the transfer ends at A_{n-1} = t + s + wire(B) + L. The slots
  /// end as the loop leaves them: the K smallest (all <= t) replaced in turn by the arrivals of
  /// the last min(n, K) chunks (their heap order is immaterial: only their values are read).
  std::optional<sim::Time> book_idle(Lane& l, std::int64_t n, std::int64_t bytes) {
    std::vector<sim::Time>& slots = *l.slot_free;
    const auto k = static_cast<std::int64_t>(slots.size());
    const sim::Time t = sim_->now();
    if (n < 1 || (!slots_never_wait_ && n > k) || l.wire->free_at > t) return std::nullopt;
    for (const sim::Time free_at : slots) {
      if (free_at > t) return std::nullopt;
    }
    if (!params_.wire_in_range(bytes)) return std::nullopt;  // the loop throws at its chunk
    const sim::Time wire = params_.wire_time(bytes);
    // setup, latency < 10^12 ps and wire < 2^63: the sum does not wrap; horizon >= t.
    if (setup_ + wire + latency_ > sim_->quiet_horizon() - t) return std::nullopt;
    const std::int64_t c = params_.dma.chunk_bytes;
    const sim::Time start = t + setup_;  // E_j = start + wire(end_j)
    const auto arrival = [&](std::int64_t j) {
      return start + params_.wire_time(std::min((j + 1) * c, bytes)) + latency_;
    };
    if (n >= k) {
      // Every slot now holds one of the last K arrivals; ascending order is a min-heap.
      for (std::int64_t i = 0; i < k; ++i) slots[static_cast<std::size_t>(i)] = arrival(n - k + i);
    } else {
      // The loop pops the n smallest slots (all <= t) and pushes the n arrivals (all >= t,
      // ascending: wire() does not decrease): the k - n largest old ones stay. Sorted, those
      // first and the arrivals after them: the same values, in ascending order (a min-heap),
      // without n pops and pushes.
      std::sort(slots.begin(), slots.end());
      std::move(slots.begin() + n, slots.end(), slots.begin());
      for (std::int64_t j = 0; j < n; ++j) slots[static_cast<std::size_t>(k - n + j)] = arrival(j);
    }
    l.wire->free_at = start + wire;
    l.wire->busy.add(wire);
    l.chunks.add(static_cast<std::uint64_t>(n));
    return start + wire + latency_;
  }

  /// Books chunks a, a + 1, ... of a transfer of `bytes` (n chunks) at once while they run
  /// steadily, as the chunk loop would one by one; returns how many (0: none, the loop books a).
  /// With the slots sorted s_0 <= ... <= s_{K-1} and E_{a-1} the wire's free time:
  ///   E_j = E_{a-1} + wire(end_j) - wire(o_a)   (back to back on the wire)
  ///   A_j = E_j + L                              (arrival)
  ///   G_j = max(t, s_{j-a}) for j - a < K, else A_{j-K}   (the slot granted)
  /// which is the loop's schedule when every chunk finds the wire busy past its setup,
  /// G_j + s <= E_{j-1} (checked for the first K; after them the K - 1 full chunks between a
  /// slot's two uses outlast L + s: slots_never_wait), when the slots all free before the first
  /// arrival (s_{K-1} <= A_a: they are granted in order before the transfer's own), and when
  /// nothing else can happen up to G_j (G_j <= horizon). The slots end holding the last K
  /// arrivals (their heap order is immaterial: only their values are read).
  std::int64_t book_steady(Lane& l, std::int64_t a, std::int64_t n, std::int64_t bytes,
                           sim::Time horizon, Run& run) {
    std::vector<sim::Time>& slots = *l.slot_free;
    const std::size_t k = slots.size();
    const std::int64_t c = params_.dma.chunk_bytes;
    if (!params_.wire_in_range(bytes)) return 0;  // the loop throws at its chunk
    const auto end_of = [&](std::int64_t j) { return std::min((j + 1) * c, bytes); };
    const sim::Time e0 = l.wire->free_at;  // E_{a-1}
    const sim::Time w0 = run.wire_done;    // wire(o_a)
    const auto wire_end = [&](std::int64_t j) { return e0 + params_.wire_time(end_of(j)) - w0; };
    std::array<sim::Time, 16> few{};
    std::vector<sim::Time> many(k > few.size() ? k : 0);
    sim::Time* const sorted = k > few.size() ? many.data() : few.data();
    std::copy(slots.begin(), slots.end(), sorted);
    std::sort(sorted, sorted + k);
    if (sorted[k - 1] > wire_end(a) + latency_) return 0;
    const auto grant = [&](std::int64_t j) {
      const auto i = static_cast<std::size_t>(j - a);
      return i < k ? std::max(run.t, sorted[i])
                   : wire_end(j - static_cast<std::int64_t>(k)) + latency_;
    };
    // The first K chunks must find the wire busy past their setup; the stretch ends before
    // the first that does not.
    std::int64_t last = n - 1;
    for (std::int64_t j = a; j <= last && j - a < static_cast<std::int64_t>(k); ++j) {
      if (grant(j) + setup_ > (j == a ? e0 : wire_end(j - 1))) last = j - 1;
    }
    if (last < a || grant(a) > horizon) return 0;
    // The last chunk granted by the horizon (grants do not decrease).
    if (grant(last) > horizon) {
      std::int64_t lo = a, hi = last;  // grant(lo) <= horizon < grant(hi)
      while (hi - lo > 1) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        (grant(mid) <= horizon ? lo : hi) = mid;
      }
      last = lo;
    }
    const std::int64_t count = last - a + 1;
    // The slots: the sorted ones not yet granted, then the arrivals of chunks a..last.
    const auto kept =
        static_cast<std::size_t>(std::max<std::int64_t>(0, static_cast<std::int64_t>(k) - count));
    for (std::size_t i = 0; i < k; ++i) {
      slots[i] = i < kept ? sorted[k - kept + i]
                          : wire_end(last - static_cast<std::int64_t>(k - 1 - i)) + latency_;
    }
    std::make_heap(slots.begin(), slots.end(), std::greater<sim::Time>());
    const sim::Time wire_last = params_.wire_time(end_of(last));
    l.wire->busy.add(wire_last - w0);
    l.wire->free_at = e0 + wire_last - w0;
    l.chunks.add(static_cast<std::uint64_t>(count));
    run.last_arrival = std::max(run.last_arrival, l.wire->free_at + latency_);
    run.t = std::max(run.t, grant(last));
    run.wire_done = wire_last;
    return count;
  }

  sim::Simulator* sim_;
  sim::Time created_;
  DmaLink::Params params_;  ///< a copy: the model may outlive the platform's instance
  sim::Time setup_;
  sim::Time latency_;
  bool slots_never_wait_;  ///< DmaLink::slots_never_wait: book_steady's stretches may be long
  Lane h2c_;
  Lane c2h_;
  sim::Timeline* timeline_ = nullptr;
  sim::Timeline::TrackId h2c_track_{}, c2h_track_{};
};

std::unique_ptr<LinkModel> DmaLink::make_model(sim::Simulator& sim) const {
  return std::make_unique<DmaModel>(sim, *this);
}

}  // namespace

EDX_REGISTER_COMPONENT(Link, DmaLink, "dma",
                       "a wire of a bandwidth and latency fed by a DMA engine in chunks, K "
                       "requests in flight (PCIe 3.0 x8, AXI4; paper Sec. VII-A)");

}  // namespace edx::arch
