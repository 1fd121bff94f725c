#pragma once
// Reads a results database written by `edx simulate --out` (arch/results/results_db.hpp; the
// tables and columns: arch/results/schema.hpp) for `edx report` and `edx check`.
// Read-only: the database is opened with SQLITE_OPEN_READONLY and never changed.
//
// Sweep tables are optional (written by `edx sweep`, arch/sweep/sweep_runner.cpp, docs/SWEEPS.md):
//   sweeps(sweep_id, spec, base, trace, points, spec_json)   spec_json.objectives:
//          [{"minimize"|"maximize": metric}, ...]
//   sweep_points(sweep_id, point, run_id, parameters_json, metrics_json, feasible, pareto)
// When both are there the report draws each sweep's points and Pareto front (docs/REPORTS.md).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace edx::reports {

struct FrameRow {
  std::string variant;  ///< baseline | accelerated
  std::int64_t frame_id = 0;
  std::string mode;  ///< registration | vio | slam | none
  double frontend_ms = 0, backend_ms = 0, e2e_ms = 0, host_busy_ms = 0;
  int offloaded = 0;
  double energy_j = 0;
};

struct LatencyRow {
  std::string variant, mode, stage;
  std::int64_t count = 0;
  double mean = 0, sd = 0, rsd = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
};

struct ThroughputRow {
  std::string variant;
  double fps_without_pipelining = 0, fps_with_pipelining = 0;
};

struct EnergyRow {
  std::string variant, mode;
  double mean_j = 0, sd_j = 0, p99_j = 0, max_j = 0;
};

/// One accelerable kernel invocation; accel_ms is NaN when the kernel does not fit the SPM.
struct OffloadRow {
  std::int64_t frame_id = 0;
  int kernel_seq = 0;
  std::string kernel;
  double size = 0, host_ms = 0, accel_ms = 0, compute_ms = 0, transfer_ms = 0;
  bool fits_spm = true, training = false, offloaded = false;
};

/// always_s is NaN when the kernel never fits the SPM (always-offload impossible).
struct ScheduleRow {
  std::string kernel;
  std::int64_t invocations = 0, offloaded = 0;
  double host_only_s = 0, always_s = 0, policy_s = 0, oracle_s = 0;
  double r_squared_train = 0, r_squared_eval = 0, gap_to_oracle = 0;
};

struct ResourceRow {
  std::string entry, group, kind;
  double lut = 0, ff = 0, dsp = 0, bram = 0;
  double ns_lut = 0, ns_ff = 0, ns_dsp = 0, ns_bram = 0;
};

struct RunData {
  std::string run_id, config_hash, trace_hash, platform, trace, policy;
  std::int64_t frames = 0;
  nlohmann::json summary;  ///< runs.summary_json: what `edx simulate --json` prints as "system"
  std::vector<FrameRow> frame_rows;
  std::vector<LatencyRow> latency;
  std::vector<ThroughputRow> throughput;
  std::vector<EnergyRow> energy;
  std::vector<OffloadRow> offload;
  std::vector<ScheduleRow> schedule;
  std::vector<ResourceRow> resources;
  /// The whole-system timeline (Perfetto JSON, table timelines) when the run was simulated with
  /// --timeline; empty otherwise. Frames [timeline_first, timeline_first + timeline_frames).
  std::string timeline_json;
  std::int64_t timeline_first = 0, timeline_frames = 0;
};

/// One design point of a sweep (table sweep_points).
struct SweepPoint {
  std::int64_t point = 0;
  std::string run_id;
  nlohmann::json parameters;  ///< {dotted platform key: value}
  nlohmann::json metrics;     ///< {objective or constraint metric: value}
  bool feasible = true, pareto = false;
  std::string workload;  ///< hash of its workload point ("" when the sweep named a trace)
  std::string error;     ///< why the point has no run (its workload failed to trace)
};

struct SweepObjectiveInfo {
  std::string metric;
  bool maximize = false;
};

/// One generation of a search's convergence (table sweep_generations).
struct SweepGeneration {
  std::int64_t generation = 0, evaluations = 0, front_size = 0;
  double hypervolume = 0;
};

struct SweepData {
  std::string sweep_id, spec;
  std::vector<SweepObjectiveInfo> objectives;  ///< from spec_json, in the spec's order
  std::vector<SweepPoint> points;              ///< ordered by point
  std::vector<SweepGeneration> generations;    ///< a search's; empty for grids and samples
  bool traces_workload = false;                ///< the spec had a workload: section
};

struct ResultsData {
  std::filesystem::path path;
  std::vector<RunData> runs;  ///< ordered by run_id
  bool has_sweeps = false;    ///< the sweeps and sweep_points tables were found
  std::vector<SweepData> sweeps;
  const RunData* find(const std::string& run_id) const;
};

/// Reads every run of `path`. Errors (std::runtime_error, one line naming the file): missing
/// file, not an SQLite database, a missing table or column, no runs, a bad summary_json.
ResultsData read_results(const std::filesystem::path& path);

}  // namespace edx::reports
