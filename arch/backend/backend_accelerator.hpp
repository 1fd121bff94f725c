#pragma once
// The backend accelerator as a DES component on sim_core (paper Sec. VI-A, Fig. 14): the five
// units of Table II, each a sim::Resource of capacity 1 on the backend clock. A kernel runs its
// ops (kernel_ops()) in trace order; each op waits for the previous one (data dependence), then
// holds its unit for op_cycles() cycles. Kernels issued concurrently share the units: an op
// waits (FIFO) while another kernel's op holds its unit. On an idle accelerator a kernel started
// on a clock edge takes exactly the analytical Σ op_cycles (accelerate_kernel()).
//
//   sim::Simulator sim;
//   BackendAccelerator accel(sim, config);
//   auto frame = [&]() -> sim::Process { co_await accel.run(kernel); };
//
// A kernel whose operands do not fit the scratchpad (accelerate_kernel().fits_spm false) runs its
// ops out of core: the units take the same cycles, and its spill traffic (plan.spill, DRAM bytes)
// is the caller's to move: the system DES puts it on the link before and after the units
// (docs/MODEL.md, "SPM spills").
#include <array>
#include <memory>
#include <string>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/kernel_replay.hpp"
#include "arch/backend/op_timing.hpp"
#include "sim_core/engine.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

class BackendAccelerator {
 public:
  /// Validates `config`. Must be destroyed before `sim`.
  BackendAccelerator(sim::Simulator& sim, BackendConfig config);
  BackendAccelerator(const BackendAccelerator&) = delete;
  BackendAccelerator& operator=(const BackendAccelerator&) = delete;

  /// Runs `kernel` (which must stay alive until the returned task completes, as it does in
  /// `co_await accel.run(kernel)`). A kernel that spills runs its ops alone (see above).
  sim::Task<void> run(const trace::KernelRecord& kernel);
  /// Runs a kernel already replayed by accelerate_kernel() on this accelerator's config (which
  /// must outlive the task). `label` names its spans (e.g. "f12 projection").
  sim::Task<void> run(const KernelAccelResult& plan, std::string label = {});

  /// Registers <prefix>.<unit>.busy (time-weighted 0/1: its mean is the unit's utilization) for
  /// the five units, <prefix>.kernels and <prefix>.ops (counters) and <prefix>.kernel_latency_us
  /// (samples: from a kernel's first request of a unit to its last op's end).
  void register_stats(sim::StatsRegistry& registry, const std::string& prefix = "backend") const;

  /// Records every op as a span on one track per unit in `group` of `timeline`, and every kernel
  /// on a "kernels" track (optional; the timeline must outlive the runs).
  void set_timeline(sim::Timeline& timeline, const std::string& group = "backend");

  const BackendConfig& config() const noexcept { return config_; }
  const sim::ClockDomain& clock() const noexcept { return clock_; }
  const sim::Resource& unit(BackendUnit u) const noexcept {
    return *units_[static_cast<std::size_t>(u)];
  }
  std::uint64_t kernels() const noexcept { return kernels_.value(); }
  std::uint64_t ops() const noexcept { return ops_.value(); }
  const sim::SampleSet& kernel_latency_us() const noexcept { return latency_us_; }

 private:
  sim::Simulator* sim_;
  BackendConfig config_;
  sim::ClockDomain clock_;
  std::array<std::unique_ptr<sim::Resource>, kBackendUnitCount> units_;
  sim::Counter kernels_, ops_;
  sim::SampleSet latency_us_;
  sim::Timeline* timeline_ = nullptr;
  std::array<sim::Timeline::TrackId, kBackendUnitCount> unit_tracks_{};
  sim::Timeline::TrackId kernel_track_{};
};

}  // namespace edx::arch
