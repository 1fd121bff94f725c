#pragma once
// The results database of `edx simulate --out results.db` (docs/MODEL.md, "Results database"):
// one SQLite file accumulating runs. A run is keyed by (config_hash, trace_hash): the FNV-1a
// hash of the platform's full JSON (every parameter, defaults included) and of the trace's meta
// table and frame count. Writing a run whose key is already there REPLACES it (its rows are
// deleted and written again), so re-running the same config on the same trace leaves one copy.
// Everything of a run is written in one transaction: on any error the transaction is rolled
// back and the file holds what it held before (a new file is removed).
//
// Tables (every row carries run_id = "<config_hash>-<trace_hash>"):
//   runs(run_id PK, config_hash, trace_hash, platform, trace, frames, policy,
//        config_json, summary_json)
//   frames(run_id, variant, frame_id, mode, frontend_ms, backend_ms, e2e_ms, host_busy_ms,
//          offloaded, energy_j)                       variant: baseline | accelerated
//   latency(run_id, variant, mode, stage, count, mean, sd, rsd, p50, p90, p99, max)
//          mode: registration | vio | slam | none | all; stage: frontend | backend | e2e
//   throughput(run_id, variant, fps_without_pipelining, fps_with_pipelining)
//   energy(run_id, variant, mode, mean_j, sd_j, p99_j, max_j)
//   offload(run_id, frame_id, kernel_seq, kernel, size, host_ms, accel_ms, compute_ms,
//           transfer_ms, fits_spm, training, offloaded)     accel_ms NULL: does not fit the SPM
//   schedule(run_id, kernel, invocations, offloaded, host_only_s, always_s, policy_s, oracle_s,
//            r_squared_train, r_squared_eval, gap_to_oracle)
//   resources(run_id, entry, grp, kind, lut, ff, dsp, bram, ns_lut, ns_ff, ns_dsp, ns_bram)
//            entries plus "total" (grp "all")
#include <filesystem>

#include "arch/system/system_model.hpp"

namespace SQLite {
class Database;
}

namespace edx::arch {

/// Checks that `db` (opened from `path`) is a results database or empty, before anything is
/// written into it; throws std::runtime_error naming the file otherwise ("x.db: is an edx trace
/// (schema version 3), not a results database").
void require_results_database(SQLite::Database& db, const std::string& path);

/// What a run writes: per_frame = false leaves out the frames and offload rows (a sweep's
/// points keep the summaries, latency, throughput, energy, schedule and resources).
struct ResultsWriteOptions {
  bool per_frame = true;
};

/// Creates the tables when needed (inside the caller's transaction, if any).
void create_results_tables(SQLite::Database& db);
/// Writes (or replaces) `result`'s run in an open database, inside the caller's transaction.
void write_results(SQLite::Database& db, const SystemResult& result,
                   const ResultsWriteOptions& options = {});
/// "<config_hash>-<trace_hash>": the key of a run.
std::string run_id_of(const std::string& config_hash, const std::string& trace_hash);

/// Writes (or replaces) `result`'s run in `path`, creating the file and tables when needed.
/// Errors: std::runtime_error naming the file.
void write_results(const std::filesystem::path& path, const SystemResult& result);

}  // namespace edx::arch
