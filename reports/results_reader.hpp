#pragma once
// Reads a results database written by `edx simulate --out` (arch/results/results_db.hpp; the
// tables and columns: arch/results/schema.hpp, docs/RESULTS.md) for `edx report` and
// `edx check`, of any schema version up to this edx's (a column a database lacks reads as NULL).
// Read-only: the database is never changed (results::open_for_reading: opened read-write when
// writable only so that its -wal/-shm files go at close).
//
// Sweep tables are optional (written by `edx sweep`, docs/SWEEPS.md): when sweeps and
// sweep_points are there the report draws each sweep's points and Pareto front (docs/REPORTS.md).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/results/schema.hpp"

namespace edx::reports {

// The rows of each table: arch/results/schema.hpp (declared once, docs/RESULTS.md).
using results::EnergyRow;
using results::FrameRow;
using results::LatencyRow;
using results::OffloadRow;
using results::ResourceRow;
using results::ScheduleRow;
using results::ThroughputRow;
/// One design point of a sweep (table sweep_points).
using SweepPoint = results::SweepPointRow;
/// One generation of a search's convergence (table sweep_generations).
using SweepGeneration = results::SweepGenerationRow;

/// A run (its row of table runs) and its rows in the other run tables (timelines: the
/// whole-system timeline when the run was simulated with --timeline, else none).
struct RunData : results::RunRow, results::RunTableRows {};

struct SweepObjectiveInfo {
  std::string metric;
  bool maximize = false;
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

/// The run of `data` named `run_id`, or, when it is "", its only run. Throws std::runtime_error
/// naming the database: no such run, or several and none chosen (listing them; --run).
const RunData& pick_run(const ResultsData& data, const std::string& run_id);

/// Reads every run of `path`. Errors (std::runtime_error, one line naming the file): missing
/// file, not an SQLite database, a missing table or column, no runs, a bad summary_json.
ResultsData read_results(const std::filesystem::path& path);

}  // namespace edx::reports
