#include "reports/results_reader.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>

#include "arch/results/schema.hpp"

namespace edx::reports {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A REAL column, NaN for NULL (results_db writes NULL for "does not fit").
double real(const SQLite::Statement& s, const char* column) {
  const SQLite::Column c = s.getColumn(column);
  return c.isNull() ? kNaN : c.getDouble();
}

std::int64_t integer(const SQLite::Statement& s, const char* column) {
  const SQLite::Column c = s.getColumn(column);
  return c.isNull() ? 0 : c.getInt64();
}

std::string text(const SQLite::Statement& s, const char* column) {
  const SQLite::Column c = s.getColumn(column);
  return c.isNull() ? std::string() : c.getString();
}

std::set<std::string> tables_of(SQLite::Database& db) {
  std::set<std::string> names;
  SQLite::Statement q(db, "SELECT name FROM sqlite_master WHERE type = 'table'");
  while (q.executeStep()) names.insert(q.getColumn(0).getString());
  return names;
}

/// Runs `sql` with run_id bound to ?1 and calls `row` for each result row.
template <typename Row>
void each_row(SQLite::Database& db, const std::string& sql, const std::string& run_id, Row row) {
  SQLite::Statement q(db, sql);
  q.bind(1, run_id);
  while (q.executeStep()) row(q);
}

void read_run(SQLite::Database& db, RunData& r) {
  each_row(db, "SELECT * FROM frames WHERE run_id = ?1 ORDER BY variant, frame_id", r.run_id,
           [&](const SQLite::Statement& q) {
             FrameRow f;
             f.variant = text(q, "variant");
             f.frame_id = integer(q, "frame_id");
             f.mode = text(q, "mode");
             f.frontend_ms = real(q, "frontend_ms");
             f.backend_ms = real(q, "backend_ms");
             f.e2e_ms = real(q, "e2e_ms");
             f.host_busy_ms = real(q, "host_busy_ms");
             f.offloaded = static_cast<int>(integer(q, "offloaded"));
             f.energy_j = real(q, "energy_j");
             r.frame_rows.push_back(std::move(f));
           });
  each_row(db, "SELECT * FROM latency WHERE run_id = ?1 ORDER BY variant, mode, stage", r.run_id,
           [&](const SQLite::Statement& q) {
             LatencyRow l;
             l.variant = text(q, "variant");
             l.mode = text(q, "mode");
             l.stage = text(q, "stage");
             l.count = integer(q, "count");
             l.mean = real(q, "mean");
             l.sd = real(q, "sd");
             l.rsd = real(q, "rsd");
             l.p50 = real(q, "p50");
             l.p90 = real(q, "p90");
             l.p99 = real(q, "p99");
             l.max = real(q, "max");
             r.latency.push_back(std::move(l));
           });
  each_row(db, "SELECT * FROM throughput WHERE run_id = ?1 ORDER BY variant DESC", r.run_id,
           [&](const SQLite::Statement& q) {
             r.throughput.push_back({text(q, "variant"), real(q, "fps_without_pipelining"),
                                     real(q, "fps_with_pipelining")});
           });
  each_row(db, "SELECT * FROM energy WHERE run_id = ?1 ORDER BY variant, mode", r.run_id,
           [&](const SQLite::Statement& q) {
             r.energy.push_back({text(q, "variant"), text(q, "mode"), real(q, "mean_j"),
                                 real(q, "sd_j"), real(q, "p99_j"), real(q, "max_j")});
           });
  each_row(db, "SELECT * FROM offload WHERE run_id = ?1 ORDER BY frame_id, kernel_seq", r.run_id,
           [&](const SQLite::Statement& q) {
             OffloadRow o;
             o.frame_id = integer(q, "frame_id");
             o.kernel_seq = static_cast<int>(integer(q, "kernel_seq"));
             o.kernel = text(q, "kernel");
             o.size = real(q, "size");
             o.host_ms = real(q, "host_ms");
             o.accel_ms = real(q, "accel_ms");
             o.compute_ms = real(q, "compute_ms");
             o.transfer_ms = real(q, "transfer_ms");
             o.fits_spm = integer(q, "fits_spm") != 0;
             o.training = integer(q, "training") != 0;
             o.offloaded = integer(q, "offloaded") != 0;
             r.offload.push_back(std::move(o));
           });
  each_row(db, "SELECT * FROM schedule WHERE run_id = ?1 ORDER BY kernel", r.run_id,
           [&](const SQLite::Statement& q) {
             ScheduleRow s;
             s.kernel = text(q, "kernel");
             s.invocations = integer(q, "invocations");
             s.offloaded = integer(q, "offloaded");
             s.host_only_s = real(q, "host_only_s");
             s.always_s = real(q, "always_s");
             s.policy_s = real(q, "policy_s");
             s.oracle_s = real(q, "oracle_s");
             s.r_squared_train = real(q, "r_squared_train");
             s.r_squared_eval = real(q, "r_squared_eval");
             s.gap_to_oracle = real(q, "gap_to_oracle");
             r.schedule.push_back(std::move(s));
           });
  each_row(
      db, "SELECT * FROM resources WHERE run_id = ?1 ORDER BY rowid", r.run_id,
      [&](const SQLite::Statement& q) {
        r.resources.push_back({text(q, "entry"), text(q, "grp"), text(q, "kind"), real(q, "lut"),
                               real(q, "ff"), real(q, "dsp"), real(q, "bram"), real(q, "ns_lut"),
                               real(q, "ns_ff"), real(q, "ns_dsp"), real(q, "ns_bram")});
      });
}

}  // namespace

const RunData* ResultsData::find(const std::string& run_id) const {
  for (const RunData& r : runs) {
    if (r.run_id == run_id) return &r;
  }
  return nullptr;
}

ResultsData read_results(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error(fmt::format("{}: no such results database", path.string()));
  }
  ResultsData out;
  out.path = path;
  try {
    SQLite::Database db(path.string(), SQLite::OPEN_READONLY);
    const std::set<std::string> tables = tables_of(db);
    for (const std::string_view t : results::kRequiredTables) {
      if (!tables.contains(std::string(t))) {
        throw std::runtime_error(
            fmt::format("not an edx results database (no table '{}'; write one with edx "
                        "simulate --out)",
                        t));
      }
    }
    const int version = db.execAndGet("PRAGMA user_version").getInt();
    if (version > results::kSchemaVersion) {
      throw std::runtime_error(
          fmt::format("results schema version {} is newer than this edx reads ({}); use a newer "
                      "edx",
                      version, results::kSchemaVersion));
    }
    SQLite::Statement runs(db, "SELECT * FROM runs ORDER BY run_id");
    while (runs.executeStep()) {
      RunData r;
      r.run_id = text(runs, "run_id");
      r.config_hash = text(runs, "config_hash");
      r.trace_hash = text(runs, "trace_hash");
      r.platform = text(runs, "platform");
      r.trace = text(runs, "trace");
      r.frames = integer(runs, "frames");
      r.policy = text(runs, "policy");
      try {
        r.summary = nlohmann::json::parse(text(runs, "summary_json"));
      } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(
            fmt::format("run {}: summary_json is not JSON ({})", r.run_id, e.what()));
      }
      out.runs.push_back(std::move(r));
    }
    if (out.runs.empty()) throw std::runtime_error("holds no runs");
    for (RunData& r : out.runs) {
      read_run(db, r);
      if (tables.contains("timelines")) {
        each_row(db, "SELECT * FROM timelines WHERE run_id = ?1", r.run_id,
                 [&](const SQLite::Statement& q) {
                   r.timeline_json = text(q, "json");
                   r.timeline_first = integer(q, "first_frame");
                   r.timeline_frames = integer(q, "frames");
                 });
      }
    }
    if (std::ranges::all_of(results::kSweepTables,
                            [&](std::string_view t) { return tables.contains(std::string(t)); })) {
      out.has_sweeps = true;
      SQLite::Statement q(db, "SELECT sweep_id, spec, spec_json FROM sweeps ORDER BY sweep_id");
      while (q.executeStep()) {
        SweepData s;
        s.sweep_id = text(q, "sweep_id");
        s.spec = text(q, "spec");
        const nlohmann::json spec = nlohmann::json::parse(text(q, "spec_json"), nullptr, false);
        if (spec.is_object() && spec.contains("objectives") && spec["objectives"].is_array()) {
          for (const nlohmann::json& o : spec["objectives"]) {
            if (!o.is_object() || o.size() != 1 || !o.begin().value().is_string()) continue;
            s.objectives.push_back(
                {o.begin().value().get<std::string>(), o.begin().key() == "maximize"});
          }
        }
        s.traces_workload = spec.is_object() && spec.contains("workload");
        // workload and error: results schema 3 (older databases lack them).
        std::set<std::string> point_columns;
        SQLite::Statement info(db, "PRAGMA table_info(sweep_points)");
        while (info.executeStep()) point_columns.insert(info.getColumn(1).getString());
        const bool v3 = point_columns.contains("workload") && point_columns.contains("error");
        SQLite::Statement p(db, "SELECT * FROM sweep_points WHERE sweep_id = ?1 ORDER BY point");
        p.bind(1, s.sweep_id);
        while (p.executeStep()) {
          SweepPoint pt;
          pt.point = integer(p, "point");
          pt.run_id = text(p, "run_id");
          pt.parameters = nlohmann::json::parse(text(p, "parameters_json"), nullptr, false);
          pt.metrics = nlohmann::json::parse(text(p, "metrics_json"), nullptr, false);
          pt.feasible = integer(p, "feasible") != 0;
          pt.pareto = integer(p, "pareto") != 0;
          if (v3) {
            pt.workload = text(p, "workload");
            pt.error = text(p, "error");
          }
          s.points.push_back(std::move(pt));
        }
        if (tables.contains("sweep_generations")) {
          SQLite::Statement g(
              db, "SELECT * FROM sweep_generations WHERE sweep_id = ?1 ORDER BY generation");
          g.bind(1, s.sweep_id);
          while (g.executeStep()) {
            s.generations.push_back({integer(g, "generation"), integer(g, "evaluations"),
                                     integer(g, "front_size"), real(g, "hypervolume")});
          }
        }
        out.sweeps.push_back(std::move(s));
      }
    }
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}: not a readable edx results database: {}", path.string(), e.what()));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: {}", path.string(), e.what()));
  }
  return out;
}

}  // namespace edx::reports
