#include "reports/results_reader.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>

#include <set>
#include <stdexcept>

#include "arch/results/schema.hpp"

namespace edx::reports {
namespace {

std::set<std::string> tables_of(SQLite::Database& db) {
  std::set<std::string> names;
  SQLite::Statement q(db, "SELECT name FROM sqlite_master WHERE type = 'table'");
  while (q.executeStep()) names.insert(q.getColumn(0).getString());
  return names;
}

/// The rows of `table` whose `key` column (run_id, sweep_id) is `id`, in `order_by`.
template <class Row>
std::vector<Row> rows_of(SQLite::Database& db, const results::Table<Row>& table, const char* key,
                         const std::string& id, const char* order_by) {
  return results::select_rows(db, table, {fmt::format("{} = ?1", key), {id}, order_by});
}

void read_run(SQLite::Database& db, RunData& r) {
  const auto of_run = [&](const auto& table, const char* order_by) {
    return rows_of(db, table, "run_id", r.run_id, order_by);
  };
  r.frame_rows = of_run(results::frames_table(), "variant, frame_id");
  r.latency = of_run(results::latency_table(), "variant, mode, stage");
  r.throughput = of_run(results::throughput_table(), "variant DESC");
  r.energy = of_run(results::energy_table(), "variant, mode");
  r.offload = of_run(results::offload_table(), "frame_id, kernel_seq");
  r.schedule = of_run(results::schedule_table(), "kernel");
  r.resources = of_run(results::resources_table(), "rowid");
  // Databases before version 1 have no timelines table: no rows.
  r.timelines = of_run(results::timelines_table(), "rowid");
  // Databases before version 5 have no frame_causes table: no rows.
  r.frame_causes = of_run(results::frame_causes_table(), "variant, run, frame_id");
  r.seed_runs = of_run(results::seed_runs_table(), "seed");
}

SweepData read_sweep(SQLite::Database& db, const results::SweepRow& row) {
  SweepData s;
  s.sweep_id = row.sweep_id;
  s.spec = row.spec;
  const nlohmann::json& spec = row.spec_json;
  if (spec.is_object() && spec.contains("objectives") && spec["objectives"].is_array()) {
    for (const nlohmann::json& o : spec["objectives"]) {
      if (!o.is_object() || o.size() != 1 || !o.begin().value().is_string()) continue;
      s.objectives.push_back({o.begin().value().get<std::string>(), o.begin().key() == "maximize"});
    }
  }
  s.traces_workload = spec.is_object() && spec.contains("workload");
  s.points = rows_of(db, results::sweep_points_table(), "sweep_id", s.sweep_id, "point");
  // Databases before version 2 have no sweep_generations table: no rows.
  s.generations =
      rows_of(db, results::sweep_generations_table(), "sweep_id", s.sweep_id, "generation");
  return s;
}

}  // namespace

const RunData* ResultsData::find(const std::string& run_id) const {
  for (const RunData& r : runs) {
    if (r.run_id == run_id) return &r;
  }
  return nullptr;
}

const RunData& pick_run(const ResultsData& data, const std::string& run_id) {
  if (!run_id.empty()) {
    if (const RunData* r = data.find(run_id)) return *r;
    throw std::runtime_error(fmt::format("{}: no run '{}' (--run)", data.path.string(), run_id));
  }
  if (data.runs.size() != 1) {
    std::string ids;
    for (const RunData& r : data.runs) ids += (ids.empty() ? "" : ", ") + r.run_id;
    throw std::runtime_error(fmt::format("{}: holds {} runs; choose one with --run ({})",
                                         data.path.string(), data.runs.size(), ids));
  }
  return data.runs.front();
}

ResultsData read_results(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error(fmt::format("{}: no such results database", path.string()));
  }
  ResultsData out;
  out.path = path;
  try {
    const std::unique_ptr<SQLite::Database> opened = results::open_for_reading(path);
    SQLite::Database& db = *opened;
    const std::set<std::string> tables = tables_of(db);
    // Every run table but those added after version 0 (timelines).
    for (const results::TableSpec* t : results::tables_of(results::TableGroup::kRun)) {
      if (t->since == 0 && !tables.contains(t->name)) {
        throw std::runtime_error(
            fmt::format("not an edx results database (no table '{}'; write one with edx "
                        "simulate --out)",
                        t->name));
      }
    }
    results::check_schema_version(db.execAndGet("PRAGMA user_version").getInt(), path.string());
    for (results::RunRow& row :
         results::select_rows(db, results::runs_table(), {"", {}, "run_id"})) {
      RunData& r = out.runs.emplace_back();
      static_cast<results::RunRow&>(r) = std::move(row);
    }
    if (out.runs.empty()) throw std::runtime_error("holds no runs");
    for (RunData& r : out.runs) read_run(db, r);
    if (tables.contains(results::sweeps_table().spec.name) &&
        tables.contains(results::sweep_points_table().spec.name)) {
      out.has_sweeps = true;
      for (const results::SweepRow& row :
           results::select_rows(db, results::sweeps_table(), {"", {}, "sweep_id"})) {
        out.sweeps.push_back(read_sweep(db, row));
      }
    }
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}: not a readable edx results database: {}", path.string(), e.what()));
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).starts_with(path.string() + ": ")) throw;
    throw std::runtime_error(fmt::format("{}: {}", path.string(), e.what()));
  }
  return out;
}

}  // namespace edx::reports
