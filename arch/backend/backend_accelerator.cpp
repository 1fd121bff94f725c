#include "arch/backend/backend_accelerator.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

namespace edx::arch {

BackendAccelerator::BackendAccelerator(sim::Simulator& sim, BackendConfig config)
    : sim_(&sim),
      config_((config.validate(), std::move(config))),
      clock_("backend", config_.clock_mhz) {
  for (BackendUnit u : kBackendUnits) {
    units_[static_cast<std::size_t>(u)] = std::make_unique<sim::Resource>(sim, 1, to_string(u));
  }
}

sim::Task<void> BackendAccelerator::run(const trace::KernelRecord& kernel) {
  const KernelAccelResult plan = accelerate_kernel(kernel, config_);
  co_await run(plan);
}

sim::Task<void> BackendAccelerator::run(const KernelAccelResult& plan, std::string label) {
  const sim::Time start = sim_->now();
  // A kernel issued between clock edges starts on the next one.
  if (clock_.next_edge(start) != start) co_await sim_->cycles(clock_, 0);
  for (const OpTiming& t : plan.ops) {
    sim::Lease lease = co_await units_[static_cast<std::size_t>(t.unit)]->acquire();
    const sim::Time begin = sim_->now();
    if (t.cycles > 0) co_await sim_->cycles(clock_, static_cast<std::uint64_t>(t.cycles));
    ops_.add();
    if (timeline_ != nullptr) {
      if (label.empty()) label = plan.kernel;
      timeline_->span(
          unit_tracks_[static_cast<std::size_t>(t.unit)],
          fmt::format("{} {} {}x{}x{}", label, trace::to_string(t.op.op), t.op.m, t.op.n, t.op.k),
          begin, sim_->now(),
          {{"cycles", t.cycles}, {"spm_bytes", t.spm_bytes}, {"spill_bytes", t.spill.bytes()}});
    }
  }
  kernels_.add();
  latency_us_.add(sim::to_us(sim_->now() - start));
  if (timeline_ != nullptr) {
    timeline_->span(kernel_track_, label.empty() ? plan.kernel : label, start, sim_->now(),
                    {{"cycles", plan.cycles}, {"ops", plan.ops.size()}});
  }
}

void BackendAccelerator::register_stats(sim::StatsRegistry& registry,
                                        const std::string& prefix) const {
  for (BackendUnit u : kBackendUnits) {
    registry.add(fmt::format("{}.{}.busy", prefix, to_string(u)), unit(u).busy());
  }
  registry.add(prefix + ".kernels", kernels_);
  registry.add(prefix + ".ops", ops_);
  registry.add(prefix + ".kernel_latency_us", latency_us_);
}

void BackendAccelerator::set_timeline(sim::Timeline& timeline, const std::string& group) {
  timeline_ = &timeline;
  kernel_track_ = timeline.track(group, "kernels");
  for (BackendUnit u : kBackendUnits) {
    unit_tracks_[static_cast<std::size_t>(u)] = timeline.track(group, to_string(u));
  }
}

}  // namespace edx::arch
