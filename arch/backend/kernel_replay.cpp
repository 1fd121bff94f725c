#include "arch/backend/kernel_replay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace edx::arch {

namespace {

/// OpCost computed (no memo).
OpCost op_cost(const trace::OpRecord& op, const MatrixUnitInstance& unit,
               const BackendConfig& config) {
  return {op_cycles(op, unit.count, config), op_spm_bytes(op, config),
          op_spill_traffic(op, config)};
}

/// The replay; `memo` optional.
KernelAccelResult replay(const trace::KernelRecord& kernel, const BackendConfig& config,
                         OpTimingMemo* memo) {
  KernelAccelResult r;
  r.kernel = kernel.kernel;
  r.derived_ops = kernel.ops.empty();
  r.spm_bytes_capacity = config.spm_bytes;
  r.unit_busy_cycles.assign(config.units.size(), 0);
  const std::vector<trace::OpRecord> ops = kernel_ops(kernel, config);
  std::vector<const MatrixUnitInstance*> unit_of(ops.size());
  for (std::size_t i = 0; i < ops.size(); ++i) {
    unit_of[i] = config.unit_for(ops[i].op);
    if (unit_of[i] == nullptr) {
      r.runnable = false;
      r.compute_s = std::numeric_limits<double>::infinity();
      r.message = fmt::format("kernel '{}': no backend unit serves its {} op (backend.units)",
                              kernel.kernel, trace::to_string(ops[i].op));
      return r;
    }
  }
  // Cycles per clock: the kernel's time is Σ over its units' clocks of their cycles / f (a few
  // clocks at most: a flat list, summed in ascending clock order as before).
  std::vector<std::pair<double, std::int64_t>> cycles_at_clock;
  std::size_t largest = 0;
  r.ops.reserve(ops.size());
  for (std::size_t i = 0; i < ops.size(); ++i) {
    const trace::OpRecord& op = ops[i];
    const MatrixUnitInstance& unit = *unit_of[i];
    const OpCost cost = memo != nullptr ? memo->cost(op, unit, config) : op_cost(op, unit, config);
    OpTiming t{op,          static_cast<std::size_t>(&unit - config.units.data()),
               unit.count,  r.cycles,
               cost.cycles, cost.spm_bytes,
               cost.spill};
    r.cycles += t.cycles;  // each op waits for the previous one
    const double clock = config.clock_of(unit);
    auto at = std::find_if(cycles_at_clock.begin(), cycles_at_clock.end(),
                           [clock](const auto& entry) { return entry.first == clock; });
    if (at == cycles_at_clock.end()) at = cycles_at_clock.insert(cycles_at_clock.end(), {clock, 0});
    at->second += t.cycles;
    if (t.spill.bytes() > 0) {
      ++r.spilled_ops;
      r.spill.read_bytes += t.spill.read_bytes;
      r.spill.write_bytes += t.spill.write_bytes;
    }
    r.unit_busy_cycles[t.unit] += t.cycles * t.copies;
    if (t.spm_bytes > r.local_bytes) {
      r.local_bytes = t.spm_bytes;
      largest = r.ops.size();
    }
    r.ops.push_back(t);
  }
  std::sort(cycles_at_clock.begin(), cycles_at_clock.end());
  for (const auto& [clock_mhz, cycles] : cycles_at_clock) {
    r.compute_s += static_cast<double>(cycles) / (clock_mhz * 1e6);
  }
  // The work by resource (the units of count > 0): a busy copy-cycle is mac_lanes MACs of the
  // unit's precision; each op reads and writes its operands in the SPM once.
  std::vector<std::size_t> resource_of(config.units.size(), 0);
  r.activity.reserve(config.units.size());
  for (std::size_t u = 0; u < config.units.size(); ++u) {
    if (config.units[u].count == 0) continue;
    resource_of[u] = r.activity.size();
    const MatrixUnitInstance& unit = config.units[u];
    cost::FrameActivity a;
    const double macs = double(r.unit_busy_cycles[u]) * unit.unit->mac_lanes();
    (unit.arithmetic() == cost::Arithmetic::kSingle ? a.single_macs : a.double_macs) = macs;
    r.activity.push_back(a);
  }
  r.compute_s_by_resource.assign(r.activity.size(), 0.0);
  for (const OpTiming& t : r.ops) {
    r.activity[resource_of[t.unit]].bram_bytes += double(t.spm_bytes) * double(t.op.batch);
    r.compute_s_by_resource[resource_of[t.unit]] +=
        static_cast<double>(t.cycles) / (config.clock_of(config.units[t.unit]) * 1e6);
  }
  r.fits_local_memory = r.local_bytes <= config.spm_bytes;
  if (!r.fits_local_memory) {
    const trace::OpRecord& op = r.ops[largest].op;
    r.message = fmt::format(
        "kernel '{}': its {} op ({}x{}x{}) needs {} B of backend SPM, capacity {} B "
        "(backend.spm_bytes): {} op(s) spill, {} B read from and {} B written to DRAM",
        kernel.kernel, trace::to_string(op.op), op.m, op.n, op.k, r.local_bytes, config.spm_bytes,
        r.spilled_ops, r.spill.read_bytes, r.spill.write_bytes);
  }
  return r;
}

}  // namespace

KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel,
                                    const BackendConfig& config) {
  return replay(kernel, config, nullptr);
}

KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel, const BackendConfig& config,
                                    OpTimingMemo& memo) {
  return replay(kernel, config, &memo);
}

std::size_t OpTimingMemo::KeyHash::operator()(const Key& key) const {
  // FNV-1a over the fields (a hash only: the map compares whole keys).
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  mix(static_cast<std::uint64_t>(key.op));
  mix(static_cast<std::uint64_t>(key.m));
  mix(static_cast<std::uint64_t>(key.n));
  mix(static_cast<std::uint64_t>(key.k));
  mix(key.flags);
  mix(static_cast<std::uint64_t>(key.batch));
  return static_cast<std::size_t>(h);
}

const OpCost& OpTimingMemo::cost(const trace::OpRecord& op, const MatrixUnitInstance& unit,
                                 const BackendConfig& config) {
  const Key key{op.op, op.m, op.n, op.k, op.flags, op.batch};
  if (const auto it = costs_.find(key); it != costs_.end()) return it->second;
  return costs_.emplace(key, op_cost(op, unit, config)).first->second;
}

double spill_seconds(const OffloadPlan& plan, const Link& link) {
  if (plan.spill.bytes() == 0) return 0.0;
  return sim::to_seconds(link.transfer_time(plan.spill.read_bytes) +
                         link.transfer_time(plan.spill.write_bytes));
}

}  // namespace edx::arch
