#pragma once
// The results database of `edx simulate --out results.db` (docs/MODEL.md, "Results database"):
// one SQLite file accumulating runs. A run is keyed by (config_hash, trace_hash): the FNV-1a
// hash of the platform's full JSON (every parameter, defaults included) and of the trace's meta
// table and frame count. Writing a run whose key is already there REPLACES it (its rows are
// deleted and written again), so re-running the same config on the same trace leaves one copy.
// Everything of a run is written in one transaction: on any error the transaction is rolled
// back and the file holds what it held before (a new file is removed).
//
// Tables and columns: arch/results/schema.hpp.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

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
/// The rows of run `run_id` in every run table (schema.hpp kRunTables), as
/// {table: [[column values...], ...]} (integers, reals, text and nulls as JSON): what a sweep
/// worker that does not own the database sends to the one that does (arch/sweep, MPI).
nlohmann::json export_run_rows(SQLite::Database& db, const std::string& run_id);
/// Writes rows exported by export_run_rows (replacing the run's rows), inside the caller's
/// transaction. Throws std::runtime_error on a malformed row set.
void import_run_rows(SQLite::Database& db, const nlohmann::json& rows);

/// "<config_hash>-<trace_hash>": the key of a run.
std::string run_id_of(const std::string& config_hash, const std::string& trace_hash);

/// Writes (or replaces) `result`'s run in `path`, creating the file and tables when needed.
/// Errors: std::runtime_error naming the file.
void write_results(const std::filesystem::path& path, const SystemResult& result);

}  // namespace edx::arch
