#pragma once
// The results database of `edx simulate --out results.db` (docs/MODEL.md, "Results database"):
// one SQLite file accumulating runs. A run is keyed by (config_hash, trace_hash): the FNV-1a
// hash of the platform's full JSON (every parameter, defaults included) and of the trace's meta
// table and frame count. Writing a run whose key is already there REPLACES it (its rows are
// deleted and written again), so re-running the same config on the same trace leaves one copy.
// Everything of a run is written in one transaction: on any error the transaction is rolled
// back and the file holds what it held before (a new file is removed).
//
// Tables and columns: arch/results/schema.hpp (docs/RESULTS.md). A simulated run's rows:
// arch/system/result_rows.hpp.
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "arch/results/schema.hpp"

namespace SQLite {
class Database;
}

namespace edx::arch {

/// Checks that `db` (opened from `path`) is a results database or empty, before anything is
/// written into it; throws std::runtime_error naming the file otherwise ("x.db: is an edx trace
/// (schema version 4), not a results database").
void require_results_database(SQLite::Database& db, const std::string& path);

/// Creates the tables of `group` when missing and brings every declared table the database has
/// to the current schema (missing columns added), then sets its version (inside the caller's
/// transaction, if any).
void create_results_tables(SQLite::Database& db,
                           results::TableGroup group = results::TableGroup::kRun);
/// Writes (or replaces) the run of `rows` in an open database, inside the caller's transaction.
void write_results(SQLite::Database& db, const results::RunRows& rows);
/// The same from the rows as values (results::run_values(rows), made by a sweep's worker so
/// that the thread owning the database only inserts them).
void write_results(SQLite::Database& db, const std::string& run_id,
                   const std::vector<results::TableValues>& tables);
/// The rows of run `run_id` in every run table, as {run_id, tables: {table: {columns: [names],
/// rows: [[values...], ...]}}} (integers, reals, text and nulls as JSON): what a sweep worker
/// that does not own the database sends to the one that does (arch/sweep, MPI).
nlohmann::json export_run_rows(SQLite::Database& db, const std::string& run_id);
/// The same of rows not written to a database.
nlohmann::json export_run_rows(const results::RunRows& rows);
/// Writes rows exported by export_run_rows (replacing the run's rows), inside the caller's
/// transaction; columns are matched by name (a column the sender lacks is NULL). Throws
/// std::runtime_error on a malformed row set.
void import_run_rows(SQLite::Database& db, const nlohmann::json& rows);

using results::run_id_of;

/// Creates the results database `path` when it does not exist yet, atomically (issue 45): `init`
/// fills a new database beside it (`<path>.tmp-<pid>`, in one transaction), which is then
/// hard-linked into place, so `path` appears only complete and never replaces a database another
/// process created meanwhile (the new one is then discarded). Returns true when this call created
/// `path`; false when it existed (`init` not run, or its work discarded). Errors:
/// std::runtime_error naming the file; nothing is left behind.
bool create_results_database(const std::filesystem::path& path,
                             const std::function<void(SQLite::Database&)>& init);

/// Writes (or replaces) the run of `rows` in `path`, creating the file and tables when needed.
/// Errors: std::runtime_error naming the file.
void write_results(const std::filesystem::path& path, const results::RunRows& rows);

}  // namespace edx::arch
