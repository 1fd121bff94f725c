#include "arch/results/results_db.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "arch/results/schema.hpp"
#include "common/atomic_file.hpp"

namespace edx::arch {
namespace {

/// Binds a double, NULL when it is not finite (a kernel that does not fit has no accel time).
void bind_real(SQLite::Statement& s, int index, double v) {
  if (std::isfinite(v)) {
    s.bind(index, v);
  } else {
    s.bind(index);
  }
}

void write_run(SQLite::Database& db, const SystemResult& r, const std::string& run_id,
               const ResultsWriteOptions& options) {
  for (const std::string_view table : results::kRunTables) {
    SQLite::Statement del(db, fmt::format("DELETE FROM {} WHERE run_id = ?", table));
    del.bind(1, run_id);
    del.exec();
  }
  SQLite::Statement run(db, "INSERT INTO runs VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)");
  run.bind(1, run_id);
  run.bind(2, r.config_hash);
  run.bind(3, r.trace_hash);
  run.bind(4, r.platform);
  run.bind(5, r.trace_path);
  run.bind(6, static_cast<std::int64_t>(r.baseline.frames.size()));
  run.bind(7, to_string(r.config.scheduler.policy));
  run.bind(8, r.config.to_json().dump());
  run.bind(9, r.to_json().dump());
  run.exec();

  SQLite::Statement frame(db, "INSERT INTO frames VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  SQLite::Statement latency(db, "INSERT INTO latency VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  SQLite::Statement throughput(db, "INSERT INTO throughput VALUES (?, ?, ?, ?)");
  SQLite::Statement energy(db, "INSERT INTO energy VALUES (?, ?, ?, ?, ?, ?, ?)");
  for (const VariantResult* v : {&r.baseline, &r.accelerated}) {
    for (const FrameResult& f : v->frames) {
      if (!options.per_frame) break;
      frame.bind(1, run_id);
      frame.bind(2, v->variant);
      frame.bind(3, static_cast<std::int64_t>(f.frame_id));
      frame.bind(4, f.mode);
      frame.bind(5, f.frontend_ms);
      frame.bind(6, f.backend_ms);
      frame.bind(7, f.e2e_ms);
      frame.bind(8, f.host_busy_ms);
      frame.bind(9, f.offloaded);
      frame.bind(10, f.energy.total_j);
      frame.exec();
      frame.reset();
    }
    for (const auto& [mode, s] : v->modes) {
      const std::pair<const char*, const Distribution*> stages[] = {
          {"frontend", &s.frontend_ms}, {"backend", &s.backend_ms}, {"e2e", &s.e2e_ms}};
      for (const auto& [stage, d] : stages) {
        latency.bind(1, run_id);
        latency.bind(2, v->variant);
        latency.bind(3, mode);
        latency.bind(4, stage);
        latency.bind(5, static_cast<std::int64_t>(d->count));
        latency.bind(6, d->mean);
        latency.bind(7, d->sd);
        latency.bind(8, d->rsd);
        latency.bind(9, d->p50);
        latency.bind(10, d->p90);
        latency.bind(11, d->p99);
        latency.bind(12, d->max);
        latency.exec();
        latency.reset();
      }
      energy.bind(1, run_id);
      energy.bind(2, v->variant);
      energy.bind(3, mode);
      energy.bind(4, s.energy_j.mean);
      energy.bind(5, s.energy_j.sd);
      energy.bind(6, s.energy_j.p99);
      energy.bind(7, s.energy_j.max);
      energy.exec();
      energy.reset();
    }
    throughput.bind(1, run_id);
    throughput.bind(2, v->variant);
    throughput.bind(3, v->fps_without_pipelining);
    throughput.bind(4, v->fps_with_pipelining);
    throughput.exec();
    throughput.reset();
  }

  SQLite::Statement offload(db, "INSERT INTO offload VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  for (const KernelDecision& d : r.decisions) {
    if (!options.per_frame) break;
    offload.bind(1, run_id);
    offload.bind(2, static_cast<std::int64_t>(d.frame_id));
    offload.bind(3, d.kernel_seq);
    offload.bind(4, d.kernel);
    offload.bind(5, d.size);
    offload.bind(6, d.host_ms);
    bind_real(offload, 7, d.accel_ms);
    offload.bind(8, d.compute_ms);
    offload.bind(9, d.transfer_ms);
    offload.bind(10, d.fits_spm ? 1 : 0);
    offload.bind(11, d.training ? 1 : 0);
    offload.bind(12, d.offloaded ? 1 : 0);
    offload.exec();
    offload.reset();
  }
  SQLite::Statement schedule(db, "INSERT INTO schedule VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  for (const KernelScheduleSummary& s : r.schedule) {
    schedule.bind(1, run_id);
    schedule.bind(2, s.kernel);
    schedule.bind(3, static_cast<std::int64_t>(s.invocations));
    schedule.bind(4, static_cast<std::int64_t>(s.offloaded));
    schedule.bind(5, s.host_only_s);
    bind_real(schedule, 6, s.always_s);
    schedule.bind(7, s.policy_s);
    schedule.bind(8, s.oracle_s);
    schedule.bind(9, s.r_squared_train);
    schedule.bind(10, s.r_squared_eval);
    schedule.bind(11, s.gap_to_oracle);
    schedule.exec();
    schedule.reset();
  }
  SQLite::Statement resource(db,
                             "INSERT INTO resources VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  const auto put = [&](const std::string& entry, const std::string& group, const std::string& kind,
                       const cost::Resources& shared, const cost::Resources& ns) {
    resource.bind(1, run_id);
    resource.bind(2, entry);
    resource.bind(3, group);
    resource.bind(4, kind);
    for (int i = 0; i < 4; ++i) {
      resource.bind(5 + i, shared[i]);
      resource.bind(9 + i, ns[i]);
    }
    resource.exec();
    resource.reset();
  };
  for (const cost::CostEntry& e : r.resources.entries) put(e.name, e.group, e.kind, e.shared, e.ns);
  put("total", "all", "total", r.resources.total.shared, r.resources.total.ns);
  if (!r.timeline_json.empty()) {
    SQLite::Statement timeline(db, "INSERT INTO timelines VALUES (?, ?, ?, ?)");
    timeline.bind(1, run_id);
    timeline.bind(2, static_cast<std::int64_t>(r.timeline_first));
    timeline.bind(3, static_cast<std::int64_t>(r.timeline_frames));
    timeline.bind(4, r.timeline_json);
    timeline.exec();
  }
}

}  // namespace

nlohmann::json export_run_rows(SQLite::Database& db, const std::string& run_id) {
  nlohmann::json rows = {{"run_id", run_id}, {"tables", nlohmann::json::object()}};
  for (std::string_view table : results::kRunTables) {
    if (!db.tableExists(std::string(table))) continue;
    SQLite::Statement q(db, fmt::format("SELECT * FROM {} WHERE run_id = ?", table));
    q.bind(1, run_id);
    nlohmann::json list = nlohmann::json::array();
    while (q.executeStep()) {
      nlohmann::json row = nlohmann::json::array();
      for (int c = 0; c < q.getColumnCount(); ++c) {
        const SQLite::Column v = q.getColumn(c);
        if (v.isNull()) {
          row.push_back(nullptr);
        } else if (v.isInteger()) {
          row.push_back(v.getInt64());
        } else if (v.isFloat()) {
          row.push_back(v.getDouble());
        } else {
          row.push_back(v.getString());
        }
      }
      list.push_back(std::move(row));
    }
    rows["tables"][std::string(table)] = std::move(list);
  }
  return rows;
}

void import_run_rows(SQLite::Database& db, const nlohmann::json& rows) {
  if (!rows.is_object() || !rows.contains("run_id") || !rows["run_id"].is_string() ||
      !rows.contains("tables") || !rows["tables"].is_object()) {
    throw std::runtime_error("run rows: expected {run_id, tables}");
  }
  const std::string run_id = rows["run_id"].get<std::string>();
  for (std::string_view table : results::kRunTables) {
    SQLite::Statement drop(db, fmt::format("DELETE FROM {} WHERE run_id = ?", table));
    drop.bind(1, run_id);
    drop.exec();
  }
  // "runs" last in kRunTables, first here: the other rows refer to it.
  for (auto it = results::kRunTables.rbegin(); it != results::kRunTables.rend(); ++it) {
    const std::string table(*it);
    if (!rows["tables"].contains(table)) continue;
    for (const nlohmann::json& row : rows["tables"][table]) {
      if (!row.is_array() || row.empty()) {
        throw std::runtime_error(fmt::format("run rows: {}: expected a list of values", table));
      }
      std::string marks;
      for (std::size_t i = 0; i < row.size(); ++i) marks += i ? ", ?" : "?";
      SQLite::Statement put(db, fmt::format("INSERT INTO {} VALUES ({})", table, marks));
      for (std::size_t i = 0; i < row.size(); ++i) {
        const int c = static_cast<int>(i) + 1;
        const nlohmann::json& v = row[i];
        if (v.is_null()) {
          put.bind(c);
        } else if (v.is_number_integer()) {
          put.bind(c, v.get<std::int64_t>());
        } else if (v.is_number()) {
          put.bind(c, v.get<double>());
        } else if (v.is_string()) {
          put.bind(c, v.get<std::string>());
        } else {
          throw std::runtime_error(
              fmt::format("run rows: {}: unexpected value {}", table, v.dump()));
        }
      }
      put.exec();
    }
  }
}

std::string run_id_of(const std::string& config_hash, const std::string& trace_hash) {
  return config_hash + "-" + trace_hash;
}

void create_results_tables(SQLite::Database& db) {
  db.exec(std::string(results::kRunTablesSql));
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
    const int version = db.execAndGet("PRAGMA user_version").getInt();
    if (version > results::kSchemaVersion) {
      throw std::runtime_error(fmt::format(
          "{}: results schema version {} is newer than this edx writes ({}); use a newer edx", path,
          version, results::kSchemaVersion));
    }
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

void write_results(SQLite::Database& db, const SystemResult& result,
                   const ResultsWriteOptions& options) {
  write_run(db, result, run_id_of(result.config_hash, result.trace_hash), options);
}

void write_results(const std::filesystem::path& path, const SystemResult& result) {
  if (path.empty()) throw std::runtime_error("results: expected a results database path");
  common::require_regular_output(path, "results database");
  // A new database is written beside the target and renamed into place when complete, so no
  // failure or kill leaves a partial file under the target name; an existing one is written in
  // one transaction (rolled back on any error).
  const bool existed = std::filesystem::exists(path);
  std::filesystem::path target = path;
  if (!existed) target += fmt::format(".tmp-{}", ::getpid());
  const std::string run_id = run_id_of(result.config_hash, result.trace_hash);
  const auto remove_temporary = [&] {
    if (existed) return;
    std::error_code ignored;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"}) {
      std::filesystem::remove(target.string() + suffix, ignored);
    }
  };
  try {
    {
      SQLite::Database db(target.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
      db.exec("PRAGMA busy_timeout = 5000");
      require_results_database(db, path.string());
      SQLite::Transaction transaction(db);  // rolled back by its destructor on an exception
      create_results_tables(db);
      write_run(db, result, run_id, {});
      transaction.commit();
    }
    if (!existed) std::filesystem::rename(target, path);
  } catch (const std::exception& e) {
    remove_temporary();
    const std::string message = e.what();
    if (message.starts_with(path.string() + ": ")) throw std::runtime_error(message);
    throw std::runtime_error(
        fmt::format("{}: cannot write the results: {}", path.string(), message));
  }
}

}  // namespace edx::arch
