// A link kind added by a test in one file, as a user would add one (issue 40): an ideal link of
// infinite bandwidth whose every transfer takes `latency_ns`, whatever its size and however many
// run at once (no wire to share, so no utilization):
//   transfer time  latency_ns for B > 0 bytes, 0 for none
//   energy         pj_per_byte a byte
#include <fmt/format.h>

#include <stdexcept>

#include "arch/link/link.hpp"

namespace edx::arch {
namespace {

class IdealLink final : public Link {
 public:
  struct Params {
    double latency_ns = 1000.0;  ///< every transfer's time
    double pj_per_byte = 0.0;
    static const FieldList<Params>& fields() {
      using C = Params;
      static const FieldList<C> list = {
          field("latency_ns", &C::latency_ns, "ns", "every transfer's time, whatever its size",
                Bounds::at_least(0).below(1e9)),
          field("pj_per_byte", &C::pj_per_byte, "pJ/byte", "energy of a byte crossing it",
                Bounds::at_least(0)),
      };
      return list;
    }
    void validate() const { check_fields(*this, "link", fields()); }
  };
  explicit IdealLink(const Params& params) : params_(params) {}

  std::string_view kind() const override { return "ideal"; }
  nlohmann::json params_json() const override { return params_to_json(params_); }
  bool full_duplex() const override { return true; }
  double pj_per_byte() const override { return params_.pj_per_byte; }
  sim::Time transfer_time(std::int64_t bytes) const override {
    if (bytes < 0) {
      throw std::runtime_error(fmt::format("link transfer: expected bytes >= 0, got {}", bytes));
    }
    return bytes == 0 ? 0 : sim::seconds(params_.latency_ns * 1e-9);
  }
  std::unique_ptr<LinkModel> make_model(sim::Simulator& sim) const override;

 private:
  Params params_;
};

/// Each transfer waits its time; nothing is shared.
class IdealModel final : public LinkModel {
 public:
  IdealModel(sim::Simulator& sim, const IdealLink& link) : sim_(&sim), link_(link) {}

  using LinkModel::set_timeline;
  using LinkModel::transfer;

  sim::Task<void> transfer(std::int64_t bytes, Direction direction, std::string label) override {
    const sim::Time begin = sim_->now();
    const sim::Time time = link_.transfer_time(bytes);
    if (time > 0) co_await sim_->delay(time);
    Lane& l = direction == Direction::HostToFpga ? h2c_ : c2h_;
    l.bytes.add(static_cast<std::uint64_t>(bytes));
    l.transfers.add();
    l.latency_us.add(sim::to_us(time));
    if (timeline_ != nullptr) {
      timeline_->span(direction == Direction::HostToFpga ? h2c_track_ : c2h_track_,
                      fmt::format("{} {} B", label.empty() ? to_string(direction) : label, bytes),
                      begin, sim_->now());
    }
  }
  void register_stats(sim::StatsRegistry& registry, const std::string& prefix) const override {
    for (const Direction d : {Direction::HostToFpga, Direction::FpgaToHost}) {
      const Lane& l = d == Direction::HostToFpga ? h2c_ : c2h_;
      const std::string base = prefix + "." + to_string(d);
      registry.add(base + ".bytes", l.bytes);
      registry.add(base + ".transfers", l.transfers);
      registry.add(base + ".latency_us", l.latency_us);
    }
  }
  void set_timeline(sim::Timeline& timeline, sim::Timeline::TrackId host_to_fpga,
                    sim::Timeline::TrackId fpga_to_host) override {
    timeline_ = &timeline;
    h2c_track_ = host_to_fpga;
    c2h_track_ = fpga_to_host;
  }
  double wire_utilization(Direction) const override { return 0.0; }

 private:
  struct Lane {
    sim::Counter bytes, transfers;
    sim::SampleSet latency_us;
  };
  sim::Simulator* sim_;
  IdealLink link_;
  Lane h2c_, c2h_;
  sim::Timeline* timeline_ = nullptr;
  sim::Timeline::TrackId h2c_track_{}, c2h_track_{};
};

std::unique_ptr<LinkModel> IdealLink::make_model(sim::Simulator& sim) const {
  return std::make_unique<IdealModel>(sim, *this);
}

}  // namespace

EDX_REGISTER_COMPONENT(Link, IdealLink, "ideal",
                       "infinite bandwidth, a fixed latency a transfer (a test's kind)");

}  // namespace edx::arch
