#pragma once
// The results database schema (docs/MODEL.md "Results database", docs/SWEEPS.md): every table
// declared once (schema.cpp, with the machinery of table.hpp), with the row struct each maps to.
// Its writers (results_db.cpp, arch/sweep/sweep_runner.cpp), its reader
// (reports/results_reader.cpp), the CSV export and docs/RESULTS.md (`edx export --reference`)
// all come from these declarations. Library edx_results_schema: reports/ uses it without
// linking the model, and it knows nothing of the model (arch/system/result_rows.hpp turns a
// simulated run into these rows).
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/results/table.hpp"

namespace edx::results {

// SQLite's user_version of a results database. 0: written before versioning (same tables, no
// timelines); 1 (2026-11-26): the timelines table; 2 (2026-11-26): sweep_generations (a
// search's convergence); 3 (2026-11-26): sweep_points.workload and .error, sweep_workloads
// (sweeps that trace their workload); 4 (2026-11-28): offload.spill_ms and .spill_bytes; 5
// (2026-11-28): frame_causes (critical-path attribution), sweep_points.bottleneck, seed_runs
// (runs of one workload over seeds). A writer
// brings an older database to this version (missing tables created, missing columns added);
// readers read every older version and refuse newer ones.
inline constexpr int kSchemaVersion = 6;

/// Throws std::runtime_error "<path>: results schema version N is newer than this edx reads
/// (kSchemaVersion); use a newer edx" for a version above kSchemaVersion, and names a negative
/// one as not an edx results database's: what every command that opens one checks first.
void check_schema_version(int version, const std::string& path);

/// "<config_hash>-<trace_hash>": the key of a run.
std::string run_id_of(const std::string& config_hash, const std::string& trace_hash);

// ---- run tables: every row carries run_id = "<config_hash>-<trace_hash>" ----

/// One simulated run (table runs).
struct RunRow {
  std::string run_id, config_hash, trace_hash, platform, trace;
  std::int64_t frames = 0;
  std::string policy;
  nlohmann::json config;   ///< the platform, every key resolved
  nlohmann::json summary;  ///< what `edx simulate --json` prints as "system"
};

/// One frame of one variant (table frames).
struct FrameRow {
  std::string run_id;
  std::string variant;  ///< baseline | accelerated
  std::int64_t frame_id = 0;
  std::string mode;  ///< registration | vio | slam | none
  double frontend_ms = 0, backend_ms = 0, e2e_ms = 0, host_busy_ms = 0;
  int offloaded = 0;
  double energy_j = 0;
};

/// One frame's critical-path attribution in one variant and run (table frame_causes;
/// arch/results/causes.hpp).
struct FrameCausesRow {
  std::string run_id;
  std::string variant;
  std::string run;  ///< isolated | streamed
  std::int64_t frame_id = 0;
  bool dropped = false;
  double latency_ms = 0;
  nlohmann::json causes;  ///< {cause: ms} of the causes that took time; they add up to latency_ms
};

/// A run of one seed of a workload simulated over seeds (`edx simulate --seeds --out`; table
/// seed_runs): the runs of one platform whose workload is the same are one figure's samples.
struct SeedRunRow {
  std::string run_id;
  std::string workload;          ///< hash of the workload without its seed (the group)
  nlohmann::json workload_json;  ///< the workload file's parameters, without the seed
  std::int64_t seed = 0;
};

/// A latency distribution of one variant, mode and stage (table latency).
struct LatencyRow {
  std::string run_id;
  std::string variant, mode, stage;
  std::int64_t count = 0;
  double mean = 0, sd = 0, rsd = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
};

struct ThroughputRow {
  std::string run_id;
  std::string variant;
  double fps_without_pipelining = 0, fps_with_pipelining = 0;
};

struct EnergyRow {
  std::string run_id;
  std::string variant, mode;
  double mean_j = 0, sd_j = 0, p99_j = 0, max_j = 0;
};

/// One accelerable kernel invocation; accel_ms is NaN when it was stored as NULL (a kernel that
/// did not fit the SPM in databases written before spills were modelled), spill_ms NaN in
/// databases before version 4.
struct OffloadRow {
  std::string run_id;
  std::int64_t frame_id = 0;
  int kernel_seq = 0;
  std::string kernel;
  double size = 0, host_ms = 0, accel_ms = 0, compute_ms = 0, transfer_ms = 0;
  bool fits_spm = true, training = false, offloaded = false;
  double spill_ms = 0;
  std::int64_t spill_bytes = 0;
};

/// The scheduler's effect on one kernel; always_s is NaN when the kernel never fits the SPM.
struct ScheduleRow {
  std::string run_id;
  std::string kernel;
  std::int64_t invocations = 0, offloaded = 0;
  double host_only_s = 0, always_s = 0, policy_s = 0, oracle_s = 0;
  double r_squared_train = 0, r_squared_eval = 0, gap_to_oracle = 0;
};

struct ResourceRow {
  std::string run_id;
  std::string entry, group, kind;
  double lut = 0, ff = 0, dsp = 0, bram = 0;
  double ns_lut = 0, ns_ff = 0, ns_dsp = 0, ns_bram = 0;
};

/// The whole-system Perfetto timeline of a run simulated with --timeline.
struct TimelineRow {
  std::string run_id;
  std::int64_t first_frame = 0, frames = 0;
  std::string json;
};

// ---- sweep tables: every row carries sweep_id (the spec's name) ----

struct SweepRow {
  std::string sweep_id, spec, base, trace;
  std::int64_t points = 0;
  nlohmann::json spec_json;  ///< the spec as run (objectives, constraints, parameters)
};

/// One design point of a sweep (table sweep_points).
struct SweepPointRow {
  std::string sweep_id;
  std::int64_t point = 0;
  std::string run_id;
  nlohmann::json parameters;  ///< {dotted platform key: value}
  nlohmann::json metrics;     ///< {objective or constraint metric: value}
  bool feasible = true, pareto = false;
  std::string workload;    ///< hash of its workload point ("" when the sweep named a trace)
  std::string error;       ///< why the point has no run (its workload failed to trace)
  std::string bottleneck;  ///< its accelerated variant's bottleneck resource (isolated, all)
};

struct SweepLockRow {
  std::string sweep_id;
  std::int64_t pid = 0;
  std::string host, started;
};

/// A run a sweep is simulating (table run_claims): another sweep on the database that needs the
/// same run waits for it instead of simulating it again (issue 45).
struct RunClaimRow {
  std::string sweep_id, run_id;
  std::int64_t pid = 0;
  std::string host, since;
};

/// One generation of a search's convergence (table sweep_generations).
struct SweepGenerationRow {
  std::string sweep_id;
  std::int64_t generation = 0, evaluations = 0, front_size = 0;
  double hypervolume = 0;
};

/// One workload point of a workload sweep and its trace (table sweep_workloads).
struct SweepWorkloadRow {
  std::string sweep_id, workload;
  nlohmann::json workload_json;  ///< its resolved parameters
  std::string trace, trace_hash, error;
  double seconds = std::numeric_limits<double>::quiet_NaN();  ///< NaN: not traced by this sweep
  std::string host;                                           ///< "" : not traced by this sweep
};

// ---- the declarations ----

const Table<RunRow>& runs_table();
const Table<FrameRow>& frames_table();
const Table<LatencyRow>& latency_table();
const Table<ThroughputRow>& throughput_table();
const Table<EnergyRow>& energy_table();
const Table<OffloadRow>& offload_table();
const Table<ScheduleRow>& schedule_table();
const Table<ResourceRow>& resources_table();
const Table<TimelineRow>& timelines_table();
const Table<FrameCausesRow>& frame_causes_table();
const Table<SeedRunRow>& seed_runs_table();
const Table<SweepRow>& sweeps_table();
const Table<SweepPointRow>& sweep_points_table();
const Table<SweepLockRow>& sweep_locks_table();
const Table<RunClaimRow>& run_claims_table();
const Table<SweepGenerationRow>& sweep_generations_table();
const Table<SweepWorkloadRow>& sweep_workloads_table();

/// Every table, run tables first (runs the first of them), in the order above.
const std::vector<const TableSpec*>& all_tables();
/// The tables of `group`, in the order above.
std::vector<const TableSpec*> tables_of(TableGroup group);
/// The declared table named `name`, or nullptr.
const TableSpec* find_table(std::string_view name);

/// A run's rows in the run tables other than runs, table by table.
struct RunTableRows {
  std::vector<FrameRow> frame_rows;
  std::vector<LatencyRow> latency;
  std::vector<ThroughputRow> throughput;
  std::vector<EnergyRow> energy;
  std::vector<OffloadRow> offload;
  std::vector<ScheduleRow> schedule;
  std::vector<ResourceRow> resources;
  std::vector<TimelineRow> timelines;  ///< none, or the run's one timeline
  std::vector<FrameCausesRow> frame_causes;
  std::vector<SeedRunRow> seed_runs;  ///< none, or the run's seed (edx simulate --seeds)
};

/// Every row of one run.
struct RunRows : RunTableRows {
  RunRow run;
};

/// Rows of one table as values.
struct TableValues {
  const TableSpec* table = nullptr;
  std::vector<ValueRow> rows;
};
/// `rows` as values, one entry per run table (tables_of(kRun) order).
std::vector<TableValues> run_values(const RunRows& rows);

/// docs/RESULTS.md: every table and column (`edx export --reference`).
std::string results_reference_markdown();

}  // namespace edx::results
