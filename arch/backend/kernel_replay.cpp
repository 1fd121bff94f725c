#include "arch/backend/kernel_replay.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace edx::arch {

nlohmann::json KernelAccelResult::to_json() const {
  nlohmann::json units = nlohmann::json::object();
  for (BackendUnit unit : kBackendUnits) units[to_string(unit)] = busy_cycles(unit);
  nlohmann::json list = nlohmann::json::array();
  for (const OpTiming& t : ops) {
    list.push_back({{"op", trace::to_string(t.op.op)},
                    {"m", t.op.m},
                    {"n", t.op.n},
                    {"k", t.op.k},
                    {"flags", t.op.flags},
                    {"unit", to_string(t.unit)},
                    {"start_cycle", t.start_cycle},
                    {"cycles", t.cycles},
                    {"spm_bytes", t.spm_bytes},
                    {"spill_read_bytes", t.spill.read_bytes},
                    {"spill_write_bytes", t.spill.write_bytes}});
  }
  return {{"kernel", kernel},
          {"derived_ops", derived_ops},
          {"cycles", cycles},
          {"seconds", seconds},
          {"unit_busy_cycles", units},
          {"spm_bytes_needed", spm_bytes_needed},
          {"spm_bytes_capacity", spm_bytes_capacity},
          {"fits_spm", fits_spm},
          {"message", message},
          {"spilled_ops", spilled_ops},
          {"spill_read_bytes", spill.read_bytes},
          {"spill_write_bytes", spill.write_bytes},
          {"spm", spm.to_json()},
          {"ops", list}};
}

KernelAccelResult accelerate_kernel(const trace::KernelRecord& kernel,
                                    const BackendConfig& config) {
  KernelAccelResult r;
  r.kernel = kernel.kernel;
  r.derived_ops = kernel.ops.empty();
  r.spm_bytes_capacity = config.spm_bytes;
  std::size_t largest = 0;
  for (const trace::OpRecord& op : kernel_ops(kernel, config)) {
    OpTiming t{op,
               unit_of(op.op),
               r.cycles,
               op_cycles(op, config),
               op_spm_bytes(op, config),
               op_spill_traffic(op, config)};
    r.cycles += t.cycles;  // each op waits for the previous one
    if (t.spill.bytes() > 0) {
      ++r.spilled_ops;
      r.spill.read_bytes += t.spill.read_bytes;
      r.spill.write_bytes += t.spill.write_bytes;
    }
    r.unit_busy_cycles[static_cast<std::size_t>(t.unit)] += t.cycles;
    if (t.spm_bytes > r.spm_bytes_needed) {
      r.spm_bytes_needed = t.spm_bytes;
      largest = r.ops.size();
    }
    r.ops.push_back(t);
  }
  r.seconds = static_cast<double>(r.cycles) / (config.clock_mhz * 1e6);
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

double spill_seconds(const KernelAccelResult& plan, const LinkSpec& link) {
  if (plan.spill.bytes() == 0) return 0.0;
  return sim::to_seconds(transfer_time(link, plan.spill.read_bytes) +
                         transfer_time(link, plan.spill.write_bytes));
}

double estimate_offload_seconds(const trace::KernelRecord& kernel, const BackendConfig& config,
                                const LinkSpec& link, const FrameTransferConfig& transfers) {
  const sim::Time transfer =
      kernel_transfer_time(link, kernel_transfer(kernel, transfers, config.matrix_format()));
  const KernelAccelResult plan = accelerate_kernel(kernel, config);
  return plan.seconds + sim::to_seconds(transfer) + spill_seconds(plan, link);
}

}  // namespace edx::arch
