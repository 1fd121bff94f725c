#include "arch/results/results_db.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/temporary_files.hpp"

namespace edx::arch {
namespace {

void delete_run(SQLite::Database& db, const std::string& run_id) {
  for (const results::TableSpec* table : results::tables_of(results::TableGroup::kRun)) {
    SQLite::Statement del(db, fmt::format("DELETE FROM {} WHERE run_id = ?", table->name));
    del.bind(1, run_id);
    del.exec();
  }
}

/// A run's rows (replacing those of its run_id), runs first.
void write_run(SQLite::Database& db, const std::string& run_id,
               const std::vector<results::TableValues>& tables) {
  delete_run(db, run_id);
  for (const results::TableValues& t : tables) results::insert_values(db, *t.table, t.rows);
}

nlohmann::json run_rows_json(const std::string& run_id,
                             const std::vector<results::TableValues>& tables) {
  nlohmann::json out = {{"run_id", run_id}, {"tables", nlohmann::json::object()}};
  for (const results::TableValues& t : tables) {
    nlohmann::json columns = nlohmann::json::array(), rows = nlohmann::json::array();
    for (const results::ColumnSpec& c : t.table->columns) columns.push_back(c.name);
    for (const results::ValueRow& row : t.rows) {
      nlohmann::json values = nlohmann::json::array();
      for (const results::Value& v : row) values.push_back(results::value_to_json(v));
      rows.push_back(std::move(values));
    }
    out["tables"][t.table->name] = {{"columns", std::move(columns)}, {"rows", std::move(rows)}};
  }
  return out;
}

/// The rows of one table of an exported run, as values in the declared column order.
std::vector<results::ValueRow> table_rows_of(const results::TableSpec& table,
                                             const nlohmann::json& exported) {
  const auto fail = [&](const std::string& what) {
    return std::runtime_error(fmt::format("run rows: {}: {}", table.name, what));
  };
  if (!exported.is_object() || !exported.contains("columns") || !exported["columns"].is_array() ||
      !exported.contains("rows") || !exported["rows"].is_array()) {
    throw fail("expected {columns, rows}");
  }
  std::vector<std::size_t> index;  // per exported column: its declared column
  for (const nlohmann::json& name : exported["columns"]) {
    if (!name.is_string()) throw fail("expected column names");
    try {
      index.push_back(table.index_of(name.get<std::string>()));
    } catch (const std::logic_error&) {
      throw fail(fmt::format("no column '{}'", name.get<std::string>()));
    }
  }
  std::vector<results::ValueRow> rows;
  for (const nlohmann::json& row : exported["rows"]) {
    if (!row.is_array() || row.size() != index.size()) {
      throw fail(fmt::format("expected a list of {} values", index.size()));
    }
    results::ValueRow values(table.columns.size());
    for (std::size_t i = 0; i < index.size(); ++i) {
      try {
        values[index[i]] = results::value_from_json(row[i], table.columns[index[i]].type);
      } catch (const std::runtime_error& e) {
        throw fail(fmt::format("{}: {}", table.columns[index[i]].name, e.what()));
      }
    }
    rows.push_back(std::move(values));
  }
  return rows;
}

}  // namespace

nlohmann::json export_run_rows(SQLite::Database& db, const std::string& run_id) {
  std::vector<results::TableValues> tables;
  for (const results::TableSpec* table : results::tables_of(results::TableGroup::kRun)) {
    if (!db.tableExists(table->name)) continue;
    tables.push_back({table, results::select_values(db, *table, {"run_id = ?1", {run_id}, ""})});
  }
  return run_rows_json(run_id, tables);
}

nlohmann::json export_run_rows(const results::RunRows& rows) {
  return run_rows_json(rows.run.run_id, results::run_values(rows));
}

void import_run_rows(SQLite::Database& db, const nlohmann::json& rows) {
  if (!rows.is_object() || !rows.contains("run_id") || !rows["run_id"].is_string() ||
      !rows.contains("tables") || !rows["tables"].is_object()) {
    throw std::runtime_error("run rows: expected {run_id, tables}");
  }
  for (const auto& [name, table] : rows["tables"].items()) {
    const results::TableSpec* spec = results::find_table(name);
    if (!spec || spec->group != results::TableGroup::kRun) {
      throw std::runtime_error(fmt::format("run rows: no run table '{}'", name));
    }
  }
  std::vector<results::TableValues> tables;
  for (const results::TableSpec* table : results::tables_of(results::TableGroup::kRun)) {
    if (!rows["tables"].contains(table->name)) continue;
    tables.push_back({table, table_rows_of(*table, rows["tables"][table->name])});
  }
  write_run(db, rows["run_id"].get<std::string>(), tables);
}

void create_results_tables(SQLite::Database& db, results::TableGroup group) {
  for (const results::TableSpec* table : results::all_tables()) {
    if (table->group == group || db.tableExists(table->name)) {
      results::create_or_upgrade(db, *table);
    }
  }
  db.exec(fmt::format("PRAGMA user_version = {}", results::kSchemaVersion));
}

void require_results_database(SQLite::Database& db, const std::string& path) {
  std::vector<std::string> tables;
  try {
    SQLite::Statement q(db, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name");
    while (q.executeStep()) tables.push_back(q.getColumn(0).getString());
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(fmt::format("{}: not a readable SQLite database: {}", path, e.what()));
  }
  const auto has = [&](const char* t) {
    return std::find(tables.begin(), tables.end(), t) != tables.end();
  };
  if (tables.empty()) return;
  if (has("runs")) {
    results::check_schema_version(db.execAndGet("PRAGMA user_version").getInt(), path);
    return;
  }
  if (has("meta") && has("frames") && has("kernels")) {
    std::string version = "?";
    try {
      SQLite::Statement v(db, "SELECT value FROM meta WHERE key = 'schema_version'");
      if (v.executeStep()) version = v.getColumn(0).getString();
    } catch (const SQLite::Exception&) {
    }
    throw std::runtime_error(fmt::format(
        "{}: is an edx trace (schema version {}), not a results database", path, version));
  }
  throw std::runtime_error(
      fmt::format("{}: not an edx results database (it has tables {} but no 'runs')", path,
                  fmt::join(tables, ", ")));
}

void write_results(SQLite::Database& db, const results::RunRows& rows) {
  write_run(db, rows.run.run_id, results::run_values(rows));
}

void write_results(SQLite::Database& db, const std::string& run_id,
                   const std::vector<results::TableValues>& tables) {
  write_run(db, run_id, tables);
}

bool create_results_database(const std::filesystem::path& path,
                             const std::function<void(SQLite::Database&)>& init) {
  if (std::filesystem::exists(path)) return false;
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path temporary =
      path.string() + fmt::format(".tmp-{}-{}", ::getpid(), counter.fetch_add(1));
  const common::TemporaryFileGuard guard(temporary);
  const auto remove_temporary = [&] {
    std::error_code ignored;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"}) {
      std::filesystem::remove(temporary.string() + suffix, ignored);
    }
  };
  try {
    {
      SQLite::Database db(temporary.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
      SQLite::Transaction transaction(db);  // rolled back by its destructor on an exception
      init(db);
      transaction.commit();
    }
    // link() fails with EEXIST instead of replacing: a database another process created since
    // the check above is kept, and this one discarded.
    std::error_code ec;
    std::filesystem::create_hard_link(temporary, path, ec);
    remove_temporary();
    if (ec == std::errc::file_exists) return false;
    if (ec) {
      throw std::runtime_error(fmt::format("cannot create it: {}", ec.message()));
    }
    return true;
  } catch (const std::exception& e) {
    remove_temporary();
    const std::string message = e.what();
    if (message.starts_with(path.string() + ": ")) throw std::runtime_error(message);
    throw std::runtime_error(fmt::format("{}: {}", path.string(), message));
  }
}

void write_results(const std::filesystem::path& path, const results::RunRows& rows) {
  if (path.empty()) throw std::runtime_error("results: expected a results database path");
  common::require_regular_output(path, "results database");
  // A new database is written beside the target and linked into place when complete
  // (create_results_database): no failure or kill leaves a partial file under the target name,
  // and two processes creating it at once both keep their run. An existing one is written in one
  // transaction (rolled back on any error).
  const auto fill = [&](SQLite::Database& db) {
    create_results_tables(db);
    write_results(db, rows);
  };
  try {
    if (create_results_database(path, fill)) return;
    SQLite::Database db(path.string(), SQLite::OPEN_READWRITE);
    db.exec("PRAGMA busy_timeout = 5000");
    require_results_database(db, path.string());
    SQLite::Transaction transaction(db);  // rolled back by its destructor on an exception
    fill(db);
    transaction.commit();
  } catch (const std::exception& e) {
    const std::string message = e.what();
    if (message.starts_with(path.string() + ": ")) throw std::runtime_error(message);
    throw std::runtime_error(
        fmt::format("{}: cannot write the results: {}", path.string(), message));
  }
}

}  // namespace edx::arch
