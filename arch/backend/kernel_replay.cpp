#include "arch/backend/kernel_replay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <map>

namespace edx::arch {

KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel,
                                    const BackendConfig& config) {
  KernelAccelResult r;
  r.kernel = kernel.kernel;
  r.derived_ops = kernel.ops.empty();
  r.spm_bytes_capacity = config.spm_bytes;
  r.unit_busy_cycles.assign(config.units.size(), 0);
  const std::vector<trace::OpRecord> ops = kernel_ops(kernel, config);
  for (const trace::OpRecord& op : ops) {
    if (config.unit_for(op.op) == nullptr) {
      r.offloadable = false;
      r.seconds = std::numeric_limits<double>::infinity();
      r.message = fmt::format("kernel '{}': no backend unit serves its {} op (backend.units)",
                              kernel.kernel, trace::to_string(op.op));
      return r;
    }
  }
  // Cycles per clock: the kernel's time is Σ over its units' clocks of their cycles / f.
  std::map<double, std::int64_t> cycles_at_clock;
  std::size_t largest = 0;
  for (const trace::OpRecord& op : ops) {
    const MatrixUnitInstance& unit = *config.unit_for(op.op);
    OpTiming t{op,
               static_cast<std::size_t>(&unit - config.units.data()),
               unit.count,
               r.cycles,
               op_cycles(op, unit.count, config),
               op_spm_bytes(op, config),
               op_spill_traffic(op, config)};
    r.cycles += t.cycles;  // each op waits for the previous one
    cycles_at_clock[config.clock_of(unit)] += t.cycles;
    if (t.spill.bytes() > 0) {
      ++r.spilled_ops;
      r.spill.read_bytes += t.spill.read_bytes;
      r.spill.write_bytes += t.spill.write_bytes;
    }
    r.unit_busy_cycles[t.unit] += t.cycles * t.copies;
    if (t.spm_bytes > r.spm_bytes_needed) {
      r.spm_bytes_needed = t.spm_bytes;
      largest = r.ops.size();
    }
    r.ops.push_back(t);
  }
  for (const auto& [clock_mhz, cycles] : cycles_at_clock) {
    r.seconds += static_cast<double>(cycles) / (clock_mhz * 1e6);
  }
  ScratchpadSpec spec;
  spec.name = "backend.spm";
  spec.word_bits = 8 * config.scalar_bytes;  // one scalar per word
  if (!r.ops.empty()) {
    spec.regions.push_back(
        {fmt::format("{}.{}", kernel.kernel, trace::to_string(r.ops[largest].op.op)),
         r.spm_bytes_needed});
  }
  r.spm = size_scratchpad(spec);
  r.fits_spm = r.spm_bytes_needed <= config.spm_bytes;
  if (!r.fits_spm) {
    const trace::OpRecord& op = r.ops[largest].op;
    r.message = fmt::format(
        "kernel '{}': its {} op ({}x{}x{}) needs {} B of backend SPM, capacity {} B "
        "(backend.spm_bytes): {} op(s) spill, {} B read from and {} B written to DRAM",
        kernel.kernel, trace::to_string(op.op), op.m, op.n, op.k, r.spm_bytes_needed,
        config.spm_bytes, r.spilled_ops, r.spill.read_bytes, r.spill.write_bytes);
  }
  return r;
}

double spill_seconds(const KernelAccelResult& plan, const Link& link) {
  if (plan.spill.bytes() == 0) return 0.0;
  return sim::to_seconds(link.transfer_time(plan.spill.read_bytes) +
                         link.transfer_time(plan.spill.write_bytes));
}

}  // namespace edx::arch
