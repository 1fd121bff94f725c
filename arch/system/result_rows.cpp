#include "arch/system/result_rows.hpp"

#include <utility>

namespace edx::arch {
namespace {

results::LatencyRow latency_row(const std::string& run_id, const std::string& variant,
                                const std::string& mode, const char* stage, const Distribution& d) {
  return {run_id, variant, mode,  stage, static_cast<std::int64_t>(d.count), d.mean, d.sd, d.rsd,
          d.p50,  d.p90,   d.p99, d.max};
}

results::ResourceRow resource_row(const std::string& run_id, const std::string& entry,
                                  const std::string& group, const std::string& kind,
                                  const cost::Resources& shared, const cost::Resources& ns) {
  return {run_id,     entry,       group,  kind,  shared.lut, shared.ff,
          shared.dsp, shared.bram, ns.lut, ns.ff, ns.dsp,     ns.bram};
}

}  // namespace

results::RunRows result_rows(const SystemResult& r, bool per_frame) {
  results::RunRows rows;
  const std::string run_id = results::run_id_of(r.config_hash, r.trace_hash);
  rows.run = {run_id,
              r.config_hash,
              r.trace_hash,
              r.platform,
              r.trace_path,
              static_cast<std::int64_t>(r.baseline.frames.size()),
              to_string(r.config.scheduler.policy),
              r.config.to_json(),
              r.to_json()};
  for (const VariantResult* v : {&r.baseline, &r.accelerated}) {
    for (const FrameResult& f : v->frames) {
      if (!per_frame) break;
      rows.frame_rows.push_back({run_id, v->variant, f.frame_id, f.mode, f.frontend_ms,
                                 f.backend_ms, f.e2e_ms, f.host_busy_ms, f.offloaded,
                                 f.energy.total_j});
    }
    for (const auto& [mode, s] : v->modes) {
      rows.latency.push_back(latency_row(run_id, v->variant, mode, "frontend", s.frontend_ms));
      rows.latency.push_back(latency_row(run_id, v->variant, mode, "backend", s.backend_ms));
      rows.latency.push_back(latency_row(run_id, v->variant, mode, "e2e", s.e2e_ms));
      rows.energy.push_back({run_id, v->variant, mode, s.energy_j.mean, s.energy_j.sd,
                             s.energy_j.p99, s.energy_j.max});
    }
    rows.throughput.push_back(
        {run_id, v->variant, v->fps_without_pipelining, v->fps_with_pipelining});
    if (per_frame && v->isolated_causes && v->streamed_causes) {
      for (auto [run, table] : {std::pair{"isolated", &*v->isolated_causes},
                                std::pair{"streamed", &*v->streamed_causes}}) {
        for (results::FrameCausesRow& row :
             results::frame_causes_rows(run_id, v->variant, run, *table)) {
          rows.frame_causes.push_back(std::move(row));
        }
      }
    }
  }
  for (const KernelDecision& d : r.decisions) {
    if (!per_frame) break;
    rows.offload.push_back({run_id, d.frame_id, d.kernel_seq, d.kernel, d.size, d.host_ms,
                            d.accel_ms, d.compute_ms, d.transfer_ms, d.fits_spm, d.training,
                            d.offloaded, d.spill_ms, d.spill_bytes});
  }
  for (const KernelScheduleSummary& s : r.schedule) {
    rows.schedule.push_back({run_id, s.kernel, static_cast<std::int64_t>(s.invocations),
                             static_cast<std::int64_t>(s.offloaded), s.host_only_s, s.always_s,
                             s.policy_s, s.oracle_s, s.r_squared_train, s.r_squared_eval,
                             s.gap_to_oracle});
  }
  for (const cost::CostEntry& e : r.resources.entries) {
    rows.resources.push_back(resource_row(run_id, e.name, e.group, e.kind, e.shared, e.ns));
  }
  rows.resources.push_back(resource_row(run_id, "total", "all", "total", r.resources.total.shared,
                                        r.resources.total.ns));
  if (!r.timeline_json.empty()) {
    rows.timelines.push_back({run_id, static_cast<std::int64_t>(r.timeline_first),
                              static_cast<std::int64_t>(r.timeline_frames), r.timeline_json});
  }
  return rows;
}

}  // namespace edx::arch
