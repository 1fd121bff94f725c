#include "arch/backend/backend_accelerator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace edx::arch {

BackendAccelerator::BackendAccelerator(sim::Simulator& sim, BackendConfig config)
    : sim_(&sim), config_((config.validate(), std::move(config))) {
  std::size_t next_resource = 0;  // resource() counts the units of count > 0
  for (const MatrixUnitInstance& u : config_.units) {
    resource_index_.push_back(next_resource);
    if (u.count > 0) ++next_resource;
    clocks_.push_back(std::make_unique<sim::ClockDomain>("backend." + u.name, config_.clock_of(u)));
    units_.push_back(u.count > 0 ? std::make_unique<sim::Resource>(
                                       sim, static_cast<std::size_t>(u.count), u.name)
                                 : nullptr);
  }
}

sim::Task<void> BackendAccelerator::run(const trace::KernelRecord& kernel) {
  const KernelAccelResult plan = accelerate_kernel(kernel, config_);
  if (!plan.runnable) throw std::runtime_error(plan.message);
  co_await run(plan);
}

sim::Task<void> BackendAccelerator::run(const KernelAccelResult& plan, std::string label,
                                        OffloadTimes times) {
  const sim::Time start = sim_->now();
  // The other copies an op takes (empty for a unit of one copy, the usual): one list for the
  // kernel, emptied after each op, so an op neither allocates nor destroys one.
  std::vector<sim::Lease> more;
  for (const OpTiming& t : plan.ops) {
    sim::Resource& unit = *units_[t.unit];
    const sim::ClockDomain& clock = *clocks_[t.unit];
    const sim::Time issued = sim_->now();
    // An op issued between its unit's clock edges starts on the next one.
    if (clock.next_edge(sim_->now()) != sim_->now()) co_await sim_->advance_cycles(clock, 0);
    sim::Lease first = co_await unit.acquire();
    // Every other copy free now shares the op's work.
    while (1 + more.size() < unit.capacity()) {
      sim::Lease copy = unit.try_acquire();
      if (!copy) break;
      more.push_back(std::move(copy));
    }
    const int copies = static_cast<int>(1 + more.size());
    const std::int64_t cycles = copies == t.copies ? t.cycles : op_cycles(t.op, copies, config_);
    const sim::Time begin = sim_->now();
    if (cycles > 0) co_await sim_->advance_cycles(clock, static_cast<std::uint64_t>(cycles));
    if (times.ps != nullptr) {
      // Run: the op's planned cycles from its start edge; the rest of its time waited.
      const sim::Time planned_end =
          cycles == t.cycles
              ? sim_->now()
              : std::min(sim_->now(), clock.time_of_cycles(clock.cycles_in(begin) +
                                                           static_cast<std::uint64_t>(t.cycles)));
      const std::size_t r = resource_index_[t.unit];
      times.run(r, planned_end - begin);
      times.wait(r, (begin - issued) + (sim_->now() - planned_end));
    }
    ops_.add();
    if (timeline_ != nullptr) {
      if (label.empty()) label = plan.kernel;
      timeline_->span(unit_tracks_[t.unit],
                      t.op.batch == 1
                          ? fmt::format("{} {} {}x{}x{}", label, trace::to_string(t.op.op), t.op.m,
                                        t.op.n, t.op.k)
                          : fmt::format("{} {} {}x{}x{} x{}", label, trace::to_string(t.op.op),
                                        t.op.m, t.op.n, t.op.k, t.op.batch),
                      begin, sim_->now(),
                      {{"cycles", cycles},
                       {"copies", copies},
                       {"spm_bytes", t.spm_bytes},
                       {"spill_bytes", t.spill.bytes()}});
    }
    // The copies go back in the order they were taken.
    first.release();
    more.clear();
  }
  kernels_.add();
  latency_us_.add(sim::to_us(sim_->now() - start));
  if (timeline_ != nullptr) {
    timeline_->span(kernel_track_, label.empty() ? plan.kernel : label, start, sim_->now(),
                    {{"cycles", plan.cycles}, {"ops", plan.ops.size()}});
  }
}

const sim::Resource* BackendAccelerator::resource(std::size_t index) const {
  for (const auto& unit : units_) {
    if (unit == nullptr) continue;
    if (index-- == 0) return unit.get();
  }
  return nullptr;
}

void BackendAccelerator::register_stats(sim::StatsRegistry& registry,
                                        const std::string& prefix) const {
  for (std::size_t i = 0; i < units_.size(); ++i) {
    if (units_[i] == nullptr) continue;
    registry.add(fmt::format("{}.{}.busy", prefix, config_.units[i].name), units_[i]->busy());
  }
  registry.add(prefix + ".kernels", kernels_);
  registry.add(prefix + ".ops", ops_);
  registry.add(prefix + ".kernel_latency_us", latency_us_);
}

void BackendAccelerator::set_timeline(sim::Timeline& timeline, const std::string& group) {
  timeline_ = &timeline;
  kernel_track_ = timeline.track(group, "kernels");
  unit_tracks_.clear();
  for (const MatrixUnitInstance& u : config_.units) {
    unit_tracks_.push_back(timeline.track(group, u.name));
  }
}

}  // namespace edx::arch
