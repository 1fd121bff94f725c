#pragma once
// The backend accelerator as a DES component on sim_core (paper Sec. VI-A, Fig. 14): each matrix
// unit instance of the platform (BackendConfig::units) a sim::Resource of `count` copies on its
// own clock. A kernel runs its ops (kernel_ops()) in trace order; each op waits for the previous
// one (data dependence), then takes a copy of its unit (FIFO) and every other copy free at that
// moment, and holds them for op_cycles() on that many copies (the copies share its work; with
// all of them it is the analytical figure). Kernels issued concurrently share the units: an op
// waits while other kernels' ops hold every copy of its unit. On an idle accelerator a kernel
// started on a clock edge takes exactly the analytical Σ op_cycles (accelerate_kernel()).
//
//   sim::Simulator sim;
//   BackendAccelerator accel(sim, config);
//   auto frame = [&]() -> sim::Process { co_await accel.run(kernel); };
//
// A kernel whose operands do not fit the scratchpad (fits_local_memory false) runs its
// ops out of core: the units take the same cycles, and its spill traffic (plan.spill, DRAM bytes)
// is the caller's to move: the system DES puts it on the link before and after the units
// (docs/MODEL.md, "SPM spills").
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "arch/backend/backend_config.hpp"
#include "arch/backend/kernel_replay.hpp"
#include "arch/backend/offload_accelerator.hpp"
#include "arch/backend/op_timing.hpp"
#include "sim_core/engine.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// The DES model of kind fpga_matrix_units (offload_accelerator.hpp).
class BackendAccelerator final : public OffloadModel {
 public:
  /// Validates `config`. Must be destroyed before `sim`.
  BackendAccelerator(sim::Simulator& sim, BackendConfig config);
  BackendAccelerator(const BackendAccelerator&) = delete;
  BackendAccelerator& operator=(const BackendAccelerator&) = delete;

  /// Runs `kernel` (which must stay alive until the returned task completes, as it does in
  /// `co_await accel.run(kernel)`). Throws std::runtime_error for a kernel it cannot run (an op
  /// no unit serves).
  sim::Task<void> run(const trace::KernelRecord& kernel);
  /// Runs a kernel already replayed by accelerate_kernel() on this accelerator's config (which
  /// must outlive the task). `label` names its spans (e.g. "f12 projection").
  /// `times` (optional): each op's time on its unit (run: its cycles as planned; wait: for a
  /// copy, for its clock edge, and the cycles beyond the plan on fewer copies), by
  /// resource() index.
  sim::Task<void> run(const KernelAccelResult& plan, std::string label = {},
                      OffloadTimes times = {});
  /// run() of a plan made by accelerate_kernel() (FpgaMatrixUnits::plan).
  sim::Task<void> run(const OffloadPlan& plan, std::string label, OffloadTimes times) override {
    return run(static_cast<const KernelAccelResult&>(plan), std::move(label), times);
  }
  using OffloadModel::run;
  /// The units of count > 0, in BackendConfig::units order (FpgaMatrixUnits::resource_names).
  const sim::Resource* resource(std::size_t index) const override;

  /// Registers <prefix>.<unit>.busy (time-weighted copies busy: its mean over the count is the
  /// unit's utilization) for every unit, <prefix>.kernels and <prefix>.ops (counters) and
  /// <prefix>.kernel_latency_us (samples: from a kernel's first request of a unit to its last
  /// op's end).
  void register_stats(sim::StatsRegistry& registry,
                      const std::string& prefix = "backend") const override;

  /// Records every op as a span on one track per unit in `group` of `timeline`, and every kernel
  /// on a "kernels" track (optional; the timeline must outlive the runs).
  void set_timeline(sim::Timeline& timeline, const std::string& group = "backend") override;

  const BackendConfig& config() const noexcept { return config_; }
  /// The units' resources, in BackendConfig::units order (an instance of count 0 has none:
  /// nullptr).
  const sim::Resource* unit(std::size_t index) const noexcept { return units_[index].get(); }
  const sim::ClockDomain& clock(std::size_t index) const noexcept { return *clocks_[index]; }
  std::uint64_t kernels() const noexcept { return kernels_.value(); }
  std::uint64_t ops() const noexcept { return ops_.value(); }
  const sim::SampleSet& kernel_latency_us() const noexcept { return latency_us_; }

 private:
  sim::Simulator* sim_;
  BackendConfig config_;
  std::vector<std::unique_ptr<sim::ClockDomain>> clocks_;
  std::vector<std::unique_ptr<sim::Resource>> units_;
  std::vector<std::size_t> resource_index_;  ///< per unit: its resource() index
  sim::Counter kernels_, ops_;
  sim::SampleSet latency_us_;
  sim::Timeline* timeline_ = nullptr;
  std::vector<sim::Timeline::TrackId> unit_tracks_;
  sim::Timeline::TrackId kernel_track_{};
};

}  // namespace edx::arch
