#pragma once
// The host <-> accelerator link as a component kind (docs/MODEL.md, "Links" and "Components"):
// one interface, its implementations beside it in arch/link/kinds/ (one file each, registered
// there by name), and the platform's one instance of it (`link:`, docs/CONFIG.md):
//
//   link: {kind: dma, preset: pcie3_x8, pj_per_byte: 80}
//
// What edx asks of a link: the time of one transfer on it when idle (the analytical system
// model, the scheduler's estimate, spills), whether its two directions are independent, the
// energy of a byte crossing it, and its DES model (LinkModel) on a simulator, which the frontend
// model (transfer 1) and the whole-system DES (every transfer, contending) await.
#include <cstdint>
#include <memory>
#include <string>

#include "arch/common/registry.hpp"
#include "sim_core/engine.hpp"

namespace edx::arch {

/// Which way the bytes go.
enum class Direction { HostToFpga, FpgaToHost };
/// "host_to_fpga" / "fpga_to_host".
const char* to_string(Direction direction);

/// A link's DES model on one Simulator (Link::make_model). Must be destroyed before it.
///
///   const std::unique_ptr<LinkModel> model = platform.link->make_model(sim);
///   co_await model->transfer(2048, Direction::FpgaToHost, "f12 results");
class LinkModel {
 public:
  virtual ~LinkModel() = default;

  /// Moves `bytes` in `direction`; completes when they have arrived. Concurrent transfers
  /// contend as the kind models it. `label` prefixes the transfer's timeline span (e.g.
  /// "f12 kalman_gain in"; empty: the direction). Throws std::runtime_error for negative bytes.
  virtual sim::Task<void> transfer(std::int64_t bytes, Direction direction, std::string label) = 0;
  /// The same without a label.
  sim::Task<void> transfer(std::int64_t bytes, Direction direction) {
    return transfer(bytes, direction, std::string());
  }

  /// Registers its stats under `prefix` ("link"): per direction d at least <prefix>.<d>.bytes,
  /// .transfers and .latency_us.
  virtual void register_stats(sim::StatsRegistry& registry, const std::string& prefix) const = 0;
  /// Records each transfer as a span on the track of its direction (optional).
  virtual void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId host_to_fpga,
                            sim::Timeline::TrackId fpga_to_host) = 0;
  /// The same with one track for both directions.
  void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId track) {
    set_timeline(timeline, track, track);
  }
  /// Share of the time from the model's creation to now that direction `d`'s wire carried
  /// bytes (on a half-duplex link both directions', on the one wire); 0 before time passed.
  virtual double wire_utilization(Direction d) const = 0;
};

/// A host <-> accelerator link.
class Link : public Component {
 public:
  static constexpr const char* kKindName = "link";
  /// Time of one transfer of `bytes` on the idle link; 0 for 0 bytes. Throws
  /// std::runtime_error for negative bytes.
  virtual sim::Time transfer_time(std::int64_t bytes) const = 0;
  /// True when the two directions do not contend (one wire each): the DES and the energy
  /// account report each direction's wire then, else one wire (`link.wire`).
  virtual bool full_duplex() const = 0;
  /// Energy of one byte crossing it, pJ (docs/MODEL.md, "Energy per frame": e_link).
  virtual double pj_per_byte() const = 0;
  /// Its DES model on `sim`, idle at sim.now().
  virtual std::unique_ptr<LinkModel> make_model(sim::Simulator& sim) const = 0;
};

/// The kind a platform without `link: {kind: ...}` has (arch/link/kinds/dma.cpp).
inline constexpr const char* kDefaultLinkKind = "dma";

}  // namespace edx::arch
