#pragma once
// The results database schema (docs/MODEL.md "Results database", docs/SWEEPS.md): the one
// definition its writers (results_db.cpp, arch/sweep/sweep_runner.cpp) and its reader
// (reports/results_reader.cpp) share, as workloads/trace/schema.hpp is for traces. Header only:
// reports/ includes it without linking the model.
//
// Every run table carries run_id = "<config_hash>-<trace_hash>":
//   runs(run_id PK, config_hash, trace_hash, platform, trace, frames, policy, config_json,
//        summary_json)
//   frames(run_id, variant, frame_id, mode, frontend_ms, backend_ms, e2e_ms, host_busy_ms,
//          offloaded, energy_j)                       variant: baseline | accelerated
//   latency(run_id, variant, mode, stage, count, mean, sd, rsd, p50, p90, p99, max)
//          mode: registration | vio | slam | none | all; stage: frontend | backend | e2e
//   throughput(run_id, variant, fps_without_pipelining, fps_with_pipelining)
//   energy(run_id, variant, mode, mean_j, sd_j, p99_j, max_j)
//   offload(run_id, frame_id, kernel_seq, kernel, size, host_ms, accel_ms, compute_ms,
//           transfer_ms, fits_spm, training, offloaded)     fits_spm 0: it spills (accel_ms
//           includes its DRAM traffic; NULL in databases written before 2026-11-26)
//   schedule(run_id, kernel, invocations, offloaded, host_only_s, always_s, policy_s, oracle_s,
//            r_squared_train, r_squared_eval, gap_to_oracle)
//   resources(run_id, entry, grp, kind, lut, ff, dsp, bram, ns_lut, ns_ff, ns_dsp, ns_bram)
//            entries plus "total" (grp "all")
//   timelines(run_id PK, first_frame, frames, json)   the whole-system Perfetto timeline of a
//            run simulated with --timeline (optional: databases before version 1 lack it)
// Sweep tables (edx sweep):
//   sweeps(sweep_id PK, spec, base, trace, points, spec_json)
//   sweep_points(sweep_id, point, run_id, parameters_json, metrics_json, feasible, pareto,
//                workload, error)  workload: the hash of the point's workload point ('' when the
//                sweep names a trace); error: why it has no run (run_id ''), else NULL (version 3)
//   sweep_workloads(sweep_id, workload, workload_json, trace, trace_hash, error, seconds, host)
//            a workload sweep's traces: per workload point its content hash, parameters, the
//            trace file in the trace store and its trace_hash (the runs' trace_hash), or the
//            error that stopped it; seconds and host of the tracing (version 3)
//   sweep_locks(sweep_id PK, pid, host, started)      the process running a sweep
//   sweep_generations(sweep_id, generation, evaluations, front_size, hypervolume)
//            a search's convergence: per generation, the distinct designs evaluated so far and
//            the hypervolume of their feasible front (version 2)
#include <array>
#include <string_view>
#include <utility>

namespace edx::results {

// SQLite's user_version of a results database. 0: written before versioning (same tables, no
// timelines); 1 (2026-11-26): the timelines table; 2 (2026-11-26): sweep_generations (a
// search's convergence); 3 (2026-11-26): sweep_points.workload and .error, sweep_workloads
// (sweeps that trace their workload). Readers refuse newer versions.
inline constexpr int kSchemaVersion = 3;

/// The tables of runs, created when missing (in the writer's transaction).
inline constexpr std::string_view kRunTablesSql = R"sql(
CREATE TABLE IF NOT EXISTS runs (run_id TEXT PRIMARY KEY, config_hash TEXT NOT NULL,
  trace_hash TEXT NOT NULL, platform TEXT NOT NULL, trace TEXT NOT NULL, frames INTEGER NOT NULL,
  policy TEXT NOT NULL, config_json TEXT NOT NULL, summary_json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS frames (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  frame_id INTEGER NOT NULL, mode TEXT NOT NULL, frontend_ms REAL, backend_ms REAL, e2e_ms REAL,
  host_busy_ms REAL, offloaded INTEGER, energy_j REAL, PRIMARY KEY (run_id, variant, frame_id));
CREATE TABLE IF NOT EXISTS latency (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  mode TEXT NOT NULL, stage TEXT NOT NULL, count INTEGER, mean REAL, sd REAL, rsd REAL, p50 REAL,
  p90 REAL, p99 REAL, max REAL, PRIMARY KEY (run_id, variant, mode, stage));
CREATE TABLE IF NOT EXISTS throughput (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  fps_without_pipelining REAL, fps_with_pipelining REAL, PRIMARY KEY (run_id, variant));
CREATE TABLE IF NOT EXISTS energy (run_id TEXT NOT NULL, variant TEXT NOT NULL,
  mode TEXT NOT NULL, mean_j REAL, sd_j REAL, p99_j REAL, max_j REAL,
  PRIMARY KEY (run_id, variant, mode));
CREATE TABLE IF NOT EXISTS offload (run_id TEXT NOT NULL, frame_id INTEGER NOT NULL,
  kernel_seq INTEGER NOT NULL, kernel TEXT NOT NULL, size REAL, host_ms REAL, accel_ms REAL,
  compute_ms REAL, transfer_ms REAL, fits_spm INTEGER, training INTEGER, offloaded INTEGER,
  PRIMARY KEY (run_id, frame_id, kernel_seq));
CREATE TABLE IF NOT EXISTS schedule (run_id TEXT NOT NULL, kernel TEXT NOT NULL,
  invocations INTEGER, offloaded INTEGER, host_only_s REAL, always_s REAL, policy_s REAL,
  oracle_s REAL, r_squared_train REAL, r_squared_eval REAL, gap_to_oracle REAL,
  PRIMARY KEY (run_id, kernel));
CREATE TABLE IF NOT EXISTS resources (run_id TEXT NOT NULL, entry TEXT NOT NULL,
  grp TEXT NOT NULL, kind TEXT NOT NULL, lut REAL, ff REAL, dsp REAL, bram REAL, ns_lut REAL,
  ns_ff REAL, ns_dsp REAL, ns_bram REAL);
CREATE TABLE IF NOT EXISTS timelines (run_id TEXT PRIMARY KEY, first_frame INTEGER NOT NULL,
  frames INTEGER NOT NULL, json TEXT NOT NULL);
)sql";

/// The tables of sweeps, created by `edx sweep` when missing.
inline constexpr std::string_view kSweepTablesSql = R"sql(
CREATE TABLE IF NOT EXISTS sweeps (sweep_id TEXT PRIMARY KEY, spec TEXT NOT NULL,
  base TEXT NOT NULL, trace TEXT NOT NULL, points INTEGER NOT NULL, spec_json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sweep_points (sweep_id TEXT NOT NULL, point INTEGER NOT NULL,
  run_id TEXT NOT NULL, parameters_json TEXT NOT NULL, metrics_json TEXT NOT NULL,
  feasible INTEGER NOT NULL, pareto INTEGER NOT NULL DEFAULT 0, workload TEXT NOT NULL DEFAULT '',
  error TEXT, PRIMARY KEY (sweep_id, point));
CREATE TABLE IF NOT EXISTS sweep_locks (sweep_id TEXT PRIMARY KEY, pid INTEGER NOT NULL,
  host TEXT NOT NULL, started TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS sweep_generations (sweep_id TEXT NOT NULL, generation INTEGER NOT NULL,
  evaluations INTEGER NOT NULL, front_size INTEGER NOT NULL, hypervolume REAL NOT NULL,
  PRIMARY KEY (sweep_id, generation));
CREATE TABLE IF NOT EXISTS sweep_workloads (sweep_id TEXT NOT NULL, workload TEXT NOT NULL,
  workload_json TEXT NOT NULL, trace TEXT NOT NULL, trace_hash TEXT NOT NULL, error TEXT,
  seconds REAL, host TEXT, PRIMARY KEY (sweep_id, workload));
)sql";

/// Columns added to sweep_points by version 3, for databases written before it.
inline constexpr std::array<std::pair<std::string_view, std::string_view>, 2> kSweepPointColumnsV3{
    {{"workload", "TEXT NOT NULL DEFAULT ''"}, {"error", "TEXT"}}};

/// Tables holding a run's rows (keyed by run_id), "runs" last: replacing a run deletes from each.
inline constexpr std::array<std::string_view, 9> kRunTables{"frames",    "latency",   "throughput",
                                                            "energy",    "offload",   "schedule",
                                                            "resources", "timelines", "runs"};

/// The tables every results database has (a reader refuses a file without them; timelines is
/// optional, as databases of version 0 lack it).
inline constexpr std::array<std::string_view, 8> kRequiredTables{
    "runs", "frames", "latency", "throughput", "energy", "offload", "schedule", "resources"};

/// The sweep tables a reader needs to show sweeps (both or neither).
inline constexpr std::array<std::string_view, 2> kSweepTables{"sweeps", "sweep_points"};

}  // namespace edx::results
