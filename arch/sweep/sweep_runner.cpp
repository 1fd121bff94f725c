// Running a sweep: a thread pool over the design points, one results-database transaction per
// finished point, resume by run id, the Pareto front; CSV export.
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <future>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "arch/results/results_db.hpp"
#include "arch/results/schema.hpp"
#include "arch/sweep/search.hpp"
#include "arch/sweep/sweep.hpp"
#include "arch/system/system_model.hpp"
#include "common/atomic_file.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

/// Takes the sweep's lock row (inside the caller's write transaction): one process runs a sweep
/// on a database at a time. A lock held by a live process is refused with a line naming it; a
/// lock left by a process of this host that is gone (killed) is taken over.
void take_sweep_lock(SQLite::Database& db, const std::string& db_name,
                     const std::string& sweep_id) {
  const std::string host = host_name();
  SQLite::Statement q(db, "SELECT pid, host, started FROM sweep_locks WHERE sweep_id = ?");
  q.bind(1, sweep_id);
  if (q.executeStep()) {
    const auto pid = static_cast<pid_t>(q.getColumn(0).getInt64());
    const std::string holder = q.getColumn(1).getString();
    const bool alive = holder != host || ::kill(pid, 0) == 0 || errno == EPERM;
    if (alive && !(holder == host && pid == ::getpid())) {
      throw std::runtime_error(fmt::format(
          "{}: sweep '{}' is being run by process {} on {} since {} (wait for it, or delete its "
          "row from sweep_locks if that process is gone)",
          db_name, sweep_id, pid, holder, q.getColumn(2).getString()));
    }
  }
  q.reset();
  SQLite::Statement put(db, "INSERT OR REPLACE INTO sweep_locks VALUES (?, ?, ?, datetime('now'))");
  put.bind(1, sweep_id);
  put.bind(2, static_cast<std::int64_t>(::getpid()));
  put.bind(3, host);
  put.exec();
}

/// Objectives and constraint metrics of a run summary; feasibility.
void evaluate(const SweepSpec& spec, const nlohmann::json& summary, SweepPointResult& r) {
  r.metrics = nlohmann::json::object();
  r.objectives.clear();
  for (const SweepObjective& o : spec.objectives) {
    r.objectives.push_back(sweep_metric(summary, o.metric));
    r.metrics[o.metric] = r.objectives.back();
  }
  r.feasible = true;
  for (const SweepConstraint& c : spec.constraints) {
    const double v = sweep_metric(summary, c.metric);
    r.metrics[c.metric] = v;
    r.feasible = r.feasible && v >= c.min && v <= c.max;
  }
}

void put_point(SQLite::Database& db, const std::string& sweep_id, const SweepPointResult& r) {
  SQLite::Statement s(db, "INSERT OR REPLACE INTO sweep_points VALUES (?, ?, ?, ?, ?, ?, ?)");
  s.bind(1, sweep_id);
  s.bind(2, static_cast<std::int64_t>(r.index));
  s.bind(3, r.run_id);
  s.bind(4, r.parameters.dump());
  s.bind(5, r.metrics.dump());
  s.bind(6, r.feasible ? 1 : 0);
  s.bind(7, r.pareto ? 1 : 0);
  s.exec();
}

std::string csv_field(const std::string& v) {
  if (v.find_first_of(",\"\n\r") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) {
    q.push_back(c);
    if (c == '"') q.push_back('"');
  }
  q.push_back('"');
  return q;
}

std::string csv_value(const SQLite::Column& c) {
  if (c.isNull()) return "";
  if (c.isFloat()) return fmt::format("{}", c.getDouble());
  return csv_field(c.getString());
}

}  // namespace

nlohmann::json SweepOutcome::to_json(const SweepSpec& spec) const {
  nlohmann::json pts = nlohmann::json::array(), front_json = nlohmann::json::array();
  for (const SweepPointResult& p : points) {
    pts.push_back({{"point", p.index},
                   {"run_id", p.run_id},
                   {"parameters", p.parameters},
                   {"metrics", p.metrics},
                   {"feasible", p.feasible},
                   {"pareto", p.pareto}});
  }
  for (std::size_t i : front) front_json.push_back(points[i].index);
  nlohmann::json convergence = nlohmann::json::array();
  for (const SearchGeneration& g : generations) {
    convergence.push_back({{"generation", g.generation},
                           {"evaluations", g.evaluations},
                           {"front_size", g.front_size},
                           {"hypervolume", g.hypervolume}});
  }
  return {{"sweep", sweep_id},          {"spec", spec.to_json()}, {"total", total},
          {"generations", convergence}, {"computed", computed},   {"skipped", skipped},
          {"complete", complete},       {"seconds", seconds},     {"points", pts},
          {"pareto_front", front_json}};
}

SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options) {
  const std::filesystem::path trace_path = options.trace.empty() ? spec.trace : options.trace;
  if (trace_path.empty()) {
    throw std::runtime_error(
        fmt::format("{}: trace: no trace (give trace: or --trace)", spec.file));
  }
  const trace::TraceReader reader(trace_path);
  return run_sweep(spec, options, reader.read_all(), reader.meta(), trace_path.string());
}

SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options,
                       const std::vector<trace::FrameTrace>& frames,
                       const trace::TraceMeta& trace_meta, const std::string& trace_name) {
  const auto start = std::chrono::steady_clock::now();
  // Everything that can be checked is checked before the results database is touched.
  if (options.db.empty()) throw std::runtime_error("sweep: expected a results database path");
  if (frames.empty())
    throw std::runtime_error(fmt::format("{}: the trace has no frames", trace_name));
  const auto resolution = trace_meta.find("resolution");
  if (resolution == trace_meta.end()) {
    throw std::runtime_error(fmt::format("{}: trace meta has no resolution", trace_name));
  }
  const std::string thash = trace_hash(frames.size(), trace_meta);

  // The points, enumerated lazily (a bad value failed in SweepSpec::parse, before any work).
  const SweepPoints points(spec);
  const PlatformSource base = PlatformSource::load(spec.base);
  map_host(Platform::parse(base).host, trace_meta, trace_name);  // the trace's host speed
  SweepOutcome out;
  out.sweep_id = spec.name;
  // A search evaluates at most its population in each generation and the initial one.
  out.total = spec.nsga2 ? std::min(points.size(), spec.population * (spec.generations + 1))
                         : points.size();

  common::require_regular_output(options.db, "results database");
  // A database this sweep creates is removed again if the sweep fails before its first point
  // is stored (after that it is kept: a re-run resumes from it).
  struct RemoveNewDatabase {
    std::filesystem::path path;
    bool keep = false;
    ~RemoveNewDatabase() {
      if (keep) return;
      std::error_code ignored;
      for (const char* suffix : {"", "-journal", "-wal", "-shm"}) {
        std::filesystem::remove(path.string() + suffix, ignored);
      }
    }
  } new_database{options.db, std::filesystem::exists(options.db)};
  std::unique_ptr<SQLite::Database> db_handle;
  try {
    db_handle = std::make_unique<SQLite::Database>(options.db.string(),
                                                   SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("{}: cannot open the results database: {}", options.db.string(), e.what()));
  }
  SQLite::Database& db = *db_handle;
  db.exec("PRAGMA busy_timeout = 5000");
  require_results_database(db, options.db.string());
  {
    // IMMEDIATE: two processes starting at once are serialized here (the second waits for the
    // first's lock row, then sees it).
    SQLite::Transaction t(db, SQLite::TransactionBehavior::IMMEDIATE);
    create_results_tables(db);
    db.exec(std::string(results::kSweepTablesSql));
    take_sweep_lock(db, options.db.string(), out.sweep_id);
    SQLite::Statement sweep(db, "INSERT OR REPLACE INTO sweeps VALUES (?, ?, ?, ?, ?, ?)");
    sweep.bind(1, out.sweep_id);
    sweep.bind(2, spec.file);
    sweep.bind(3, spec.base.string());
    sweep.bind(4, trace_name);
    sweep.bind(5, static_cast<std::int64_t>(points.size()));
    sweep.bind(6, spec.to_json().dump());
    sweep.exec();
    // Points of an earlier version of the spec under this name are no longer part of it.
    SQLite::Statement stale(db, "DELETE FROM sweep_points WHERE sweep_id = ? AND point >= ?");
    stale.bind(1, out.sweep_id);
    stale.bind(2, static_cast<std::int64_t>(points.size()));
    stale.exec();
    t.commit();
  }
  // The lock row goes when this run ends, however it ends (a kill leaves it; see above).
  struct ReleaseLock {
    SQLite::Database& db;
    std::string sweep_id;
    ~ReleaseLock() {
      try {
        SQLite::Statement drop(db, "DELETE FROM sweep_locks WHERE sweep_id = ? AND pid = ?");
        drop.bind(1, sweep_id);
        drop.bind(2, static_cast<std::int64_t>(::getpid()));
        drop.exec();
      } catch (const SQLite::Exception&) {
      }
    }
  } release_lock{db, out.sweep_id};
  // WAL with synchronous = NORMAL: a commit is not fsynced, but survives the process being
  // killed (only a power cut can lose the last points; the file stays consistent). Set once the
  // sweep's lock is held, so that a refused sweep leaves the file as it was.
  db.exec("PRAGMA journal_mode = WAL");
  db.exec("PRAGMA synchronous = NORMAL");

  // The pool: workers take the next point in index order, make its platform and run id, and
  // either find its run in the database (resume: evaluated from the stored summary, not counted
  // against the limit) or simulate it. Frontend studies are shared between points with the same
  // frontend_study_key (computed once, by the first worker asking). Only finished points are
  // kept: memory grows with the points run, not with the grid.
  std::mutex mutex;       // guards db, the results, the counters, the studies, the first error
  std::mutex yaml_mutex;  // guards the YAML trees of the spec and the base
  std::map<std::size_t, SweepPointResult> finished;
  std::map<std::string, std::shared_future<FrontendStudy>> studies;
  std::set<std::size_t> claimed;  // points a worker has taken
  std::size_t simulations = 0;    // claimed, toward the limit
  bool limit_reached = false;
  std::exception_ptr error;
  const std::size_t limit =
      options.limit > 0 ? options.limit : std::numeric_limits<std::size_t>::max();
  const auto finish = [&](SweepPointResult r, const SystemResult* simulated) {
    std::lock_guard<std::mutex> lock(mutex);
    SQLite::Transaction t(db);
    if (simulated) write_results(db, *simulated, ResultsWriteOptions{options.per_frame});
    put_point(db, out.sweep_id, r);
    t.commit();
    new_database.keep = true;
    (simulated ? out.computed : out.skipped) += 1;
    const std::size_t done = finished.size() + 1;
    if (options.progress) options.progress(done, out.total, r);
    finished.emplace(r.index, std::move(r));
  };
  // One point: its platform and run id, then its run from the database (resume: evaluated
  // from the stored summary, not counted against the limit) or simulated. Returns false when
  // the limit stops the sweep.
  const auto run_point = [&](std::size_t index) {
    const SweepPoint point = points.at(index);
    // yaml-cpp nodes are not safe to read from two threads (even const access may touch
    // their shared memory), and the base and the spec's values are shared: one at a time.
    const Platform platform = [&] {
      std::lock_guard<std::mutex> lock(yaml_mutex);
      return sweep_platform(spec, point, base);
    }();
    SweepPointResult r;
    r.index = index;
    r.parameters = point.parameters(spec);
    r.run_id = run_id_of(fnv1a_hex(platform.to_json().dump()), thash);
    std::optional<std::string> stored;
    {
      std::lock_guard<std::mutex> lock(mutex);
      SQLite::Statement q(db, "SELECT summary_json FROM runs WHERE run_id = ?");
      q.bind(1, r.run_id);
      if (q.executeStep()) {
        stored = q.getColumn(0).getString();
      } else if (simulations >= limit) {
        limit_reached = true;
        return false;
      } else {
        ++simulations;
      }
    }
    if (stored) {
      evaluate(spec, nlohmann::json::parse(*stored), r);
      finish(std::move(r), nullptr);
      return true;
    }
    const std::string key = frontend_study_key(platform);
    std::shared_future<FrontendStudy> study;
    std::promise<FrontendStudy> mine;
    bool owner = false;
    {
      std::lock_guard<std::mutex> lock(mutex);
      auto it = studies.find(key);
      if (it == studies.end()) {
        it = studies.emplace(key, mine.get_future().share()).first;
        owner = true;
      }
      study = it->second;
    }
    if (owner) {
      try {
        mine.set_value(study_frontend(platform, frames, trace_meta, trace_name));
      } catch (...) {
        mine.set_exception(std::current_exception());
      }
    }
    const SystemResult result =
        simulate_system(platform, frames, trace_meta, trace_name, study.get());
    evaluate(spec, result.to_json(), r);
    r.computed = true;
    finish(std::move(r), &result);
    return true;
  };
  // The pool: workers take the next of `count` points (`index_at(i)`, the i-th) in order; a
  // point already taken (a search may ask for it twice) is skipped. Only finished points are
  // kept: memory grows with the points run, not with the grid.
  const auto run_pool = [&](std::size_t count,
                            const std::function<std::size_t(std::size_t)>& index_at) {
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
      for (;;) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (error || limit_reached) return;
        }
        const std::size_t i = next++;
        if (i >= count) return;
        const std::size_t index = index_at(i);
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (!claimed.insert(index).second) continue;
        }
        try {
          if (!run_point(index)) return;
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex);
          if (!error) error = std::current_exception();
          return;
        }
      }
    };
    std::vector<std::thread> pool;
    const int jobs = std::max(1, std::min<int>(options.jobs, int(std::max<std::size_t>(1, count))));
    for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
  };
  if (spec.nsga2) {
    // The search asks for a generation at a time; a design it asked for before is read from
    // `finished`. The limit stops it (a re-run replays the same generations from the database).
    struct LimitReached {};
    try {
      out.generations = run_nsga2(spec, points, [&](const std::vector<std::size_t>& indices) {
        run_pool(indices.size(), [&](std::size_t i) { return indices[i]; });
        if (limit_reached) throw LimitReached{};
        std::vector<DesignFitness> fitness;
        for (std::size_t index : indices) {
          const SweepPointResult& r = finished.at(index);
          DesignFitness f{r.objectives, {}, r.feasible};
          for (const SweepConstraint& c : spec.constraints) {
            f.constraints.push_back(r.metrics.at(c.metric).get<double>());
          }
          fitness.push_back(std::move(f));
        }
        return fitness;
      });
    } catch (const LimitReached&) {
    }
  } else {
    run_pool(points.size(), [](std::size_t i) { return i; });
  }

  for (auto& [index, r] : finished) out.points.push_back(std::move(r));
  out.complete = spec.nsga2 ? !limit_reached : out.points.size() == points.size();
  if (out.complete) {
    // The front over the feasible points.
    std::vector<std::size_t> feasible;
    std::vector<std::vector<double>> values;
    for (std::size_t i = 0; i < out.points.size(); ++i) {
      if (!out.points[i].feasible) continue;
      feasible.push_back(i);
      values.push_back(out.points[i].objectives);
    }
    std::vector<bool> maximize;
    for (const SweepObjective& o : spec.objectives) maximize.push_back(o.maximize);
    for (std::size_t f : pareto_front(values, maximize)) {
      out.front.push_back(feasible[f]);
      out.points[feasible[f]].pareto = true;
    }
    SQLite::Transaction t(db);
    for (const SweepPointResult& r : out.points) put_point(db, out.sweep_id, r);
    SQLite::Statement stale(db, "DELETE FROM sweep_generations WHERE sweep_id = ?");
    stale.bind(1, out.sweep_id);
    stale.exec();
    SQLite::Statement g(db, "INSERT INTO sweep_generations VALUES (?, ?, ?, ?, ?)");
    for (const SearchGeneration& row : out.generations) {
      g.bind(1, out.sweep_id);
      g.bind(2, static_cast<std::int64_t>(row.generation));
      g.bind(3, static_cast<std::int64_t>(row.evaluations));
      g.bind(4, static_cast<std::int64_t>(row.front_size));
      g.bind(5, row.hypervolume);
      g.exec();
      g.reset();
    }
    t.commit();
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::string format_sweep(const SweepSpec& spec, const SweepOutcome& o) {
  std::string text =
      fmt::format("sweep      {}: {} points ({} simulated, {} from the database) in {:.2f} s{}\n",
                  o.sweep_id, o.total, o.computed, o.skipped, o.seconds,
                  o.complete ? ""
                             : fmt::format("; stopped by the limit, {} left (re-run to resume)",
                                           o.total - o.points.size()));
  std::string header = fmt::format("{:>6}", "point");
  for (const SweepParameter& p : spec.parameters)
    header += fmt::format(" {:>14}", p.key.substr(p.key.rfind('.') + 1));
  for (const SweepObjective& obj : spec.objectives) {
    header += fmt::format(" {:>14}", (obj.maximize ? "max " : "min ") + obj.metric.substr(0, 10));
  }
  header += "  feasible pareto\n";
  const auto row = [&](const SweepPointResult& r) {
    std::string line = fmt::format("{:>6}", r.index);
    for (const SweepParameter& p : spec.parameters) {
      line += fmt::format(" {:>14}", r.parameters[p.key].get<std::string>());
    }
    for (double v : r.objectives) line += fmt::format(" {:>14.4g}", v);
    return line + fmt::format("  {:<8} {}\n", r.feasible ? "yes" : "no", r.pareto ? "*" : "");
  };
  text += header;
  for (const SweepPointResult& r : o.points) text += row(r);
  if (!o.generations.empty()) {
    text += "search     generation  evaluated  front  hypervolume\n";
    for (const SearchGeneration& g : o.generations) {
      text += fmt::format("           {:>10} {:>10} {:>6}  {:.6g}\n", g.generation, g.evaluations,
                          g.front_size, g.hypervolume);
    }
  }
  if (o.complete) {
    text += fmt::format("pareto     {} of {} feasible points non-dominated:\n", o.front.size(),
                        std::count_if(o.points.begin(), o.points.end(),
                                      [](const SweepPointResult& r) { return r.feasible; }));
    text += header;
    for (std::size_t i : o.front) text += row(o.points[i]);
  }
  return text;
}

namespace {

std::size_t export_csv_from(const std::filesystem::path& db_path, const std::string& table,
                            const std::string& sweep, const std::filesystem::path& out) {
  SQLite::Database db(db_path.string(), SQLite::OPEN_READONLY);
  std::string csv;
  std::size_t rows = 0;
  if (!sweep.empty()) {
    if (!db.tableExists("sweep_points")) {
      throw std::runtime_error(fmt::format("{}: no sweeps in this database", db_path.string()));
    }
    SQLite::Statement q(
        db,
        "SELECT point, run_id, parameters_json, metrics_json, feasible, pareto FROM "
        "sweep_points WHERE sweep_id = ? ORDER BY point");
    q.bind(1, sweep);
    std::vector<std::string> params, metrics;
    std::vector<std::string> lines;
    while (q.executeStep()) {
      const nlohmann::json p = nlohmann::json::parse(q.getColumn(2).getString());
      const nlohmann::json m = nlohmann::json::parse(q.getColumn(3).getString());
      if (rows == 0) {
        for (const auto& [k, v] : p.items()) params.push_back(k);
        for (const auto& [k, v] : m.items()) metrics.push_back(k);
      }
      std::string line =
          fmt::format("{},{}", q.getColumn(0).getInt64(), q.getColumn(1).getString());
      for (const std::string& k : params)
        fmt::format_to(std::back_inserter(line), ",{}", csv_field(p.value(k, std::string())));
      for (const std::string& k : metrics) {
        fmt::format_to(std::back_inserter(line), ",{}",
                       m.contains(k) ? fmt::format("{}", m[k].get<double>()) : std::string());
      }
      line += fmt::format(",{},{}", q.getColumn(4).getInt(), q.getColumn(5).getInt());
      lines.push_back(line);
      ++rows;
    }
    if (rows == 0) {
      throw std::runtime_error(fmt::format("{}: no sweep named '{}'", db_path.string(), sweep));
    }
    std::string header = "point,run_id";
    for (const std::string& k : params)
      fmt::format_to(std::back_inserter(header), ",{}", csv_field(k));
    for (const std::string& k : metrics)
      fmt::format_to(std::back_inserter(header), ",{}", csv_field(k));
    csv = header + ",feasible,pareto\n";
    for (const std::string& l : lines) fmt::format_to(std::back_inserter(csv), "{}\n", l);
  } else {
    std::set<std::string> tables;
    SQLite::Statement t(db, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name");
    while (t.executeStep()) tables.insert(t.getColumn(0).getString());
    if (!tables.contains(table)) {
      throw std::runtime_error(fmt::format("{}: --table: no table '{}' (tables: {})",
                                           db_path.string(), table, fmt::join(tables, ", ")));
    }
    SQLite::Statement q(db, fmt::format("SELECT * FROM \"{}\"", table));
    for (int c = 0; c < q.getColumnCount(); ++c) {
      fmt::format_to(std::back_inserter(csv), "{}{}", c ? "," : "", csv_field(q.getColumnName(c)));
    }
    csv += "\n";
    while (q.executeStep()) {
      for (int c = 0; c < q.getColumnCount(); ++c)
        fmt::format_to(std::back_inserter(csv), "{}{}", c ? "," : "", csv_value(q.getColumn(c)));
      csv += "\n";
      ++rows;
    }
  }
  common::write_file_atomically(out, csv);
  return rows;
}

}  // namespace

std::size_t export_csv(const std::filesystem::path& db_path, const std::string& table,
                       const std::string& sweep, const std::filesystem::path& out) {
  if (!std::filesystem::is_regular_file(db_path)) {
    throw std::runtime_error(fmt::format("{}: no such results database", db_path.string()));
  }
  try {
    return export_csv_from(db_path, table, sweep, out);
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}: not a readable edx results database: {}", db_path.string(), e.what()));
  }
}

}  // namespace edx::arch
