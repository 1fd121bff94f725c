// Running a sweep: the master that owns the results database (one transaction per finished
// point, resume by run id, the sweep lock), orders the work (workload traces first, then the
// design points whose trace is ready) for its executor's workers (sweep_engine.hpp: threads, or
// MPI ranks), and stores the Pareto front; CSV export.
#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <deque>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <utility>

#include "arch/results/results_db.hpp"
#include "arch/results/schema.hpp"
#include "arch/sweep/search.hpp"
#include "arch/sweep/sweep.hpp"
#include "arch/sweep/sweep_engine.hpp"
#include "arch/system/system_model.hpp"
#include "common/atomic_file.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

/// Whether process `pid` of this host is running: it exists (kill(pid, 0)) and is not a zombie
/// (a killed process whose parent has not reaped it, as under an init that never reaps, e.g. in
/// containers; /proc/<pid>/stat's state 'Z').
bool process_running(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno != EPERM) return false;
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t paren = text.rfind(')');  // the command name may hold spaces and parentheses
  return paren == std::string::npos || paren + 2 >= text.size() || text[paren + 2] != 'Z';
}

/// Takes the sweep's lock row (inside the caller's write transaction): one process runs a sweep
/// on a database at a time. A lock held by a live process is refused with a line naming it; a
/// lock left by a process of this host that is gone (killed) is taken over.
void take_sweep_lock(SQLite::Database& db, const std::string& db_name,
                     const std::string& sweep_id) {
  const std::string host = sweep_engine::this_host();
  SQLite::Statement q(db, "SELECT pid, host, started FROM sweep_locks WHERE sweep_id = ?");
  q.bind(1, sweep_id);
  if (q.executeStep()) {
    const auto pid = static_cast<pid_t>(q.getColumn(0).getInt64());
    const std::string holder = q.getColumn(1).getString();
    const bool alive = holder != host || process_running(pid);
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
  SQLite::Statement s(db,
                      "INSERT OR REPLACE INTO sweep_points (sweep_id, point, run_id, "
                      "parameters_json, metrics_json, feasible, pareto, workload, error) VALUES "
                      "(?, ?, ?, ?, ?, ?, ?, ?, ?)");
  s.bind(1, sweep_id);
  s.bind(2, static_cast<std::int64_t>(r.index));
  s.bind(3, r.run_id);
  s.bind(4, r.parameters.dump());
  s.bind(5, r.metrics.dump());
  s.bind(6, r.feasible ? 1 : 0);
  s.bind(7, r.pareto ? 1 : 0);
  s.bind(8, r.workload);
  if (r.error.empty()) {
    s.bind(9);
  } else {
    s.bind(9, r.error);
  }
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
    nlohmann::json point = {{"point", p.index},           {"run_id", p.run_id},
                            {"parameters", p.parameters}, {"metrics", p.metrics},
                            {"feasible", p.feasible},     {"pareto", p.pareto}};
    if (!p.workload.empty()) point["workload"] = p.workload;
    if (!p.error.empty()) point["error"] = p.error;
    pts.push_back(std::move(point));
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
          {"traced", traced},           {"failed", failed},       {"complete", complete},
          {"seconds", seconds},         {"points", pts},          {"pareto_front", front_json}};
}

namespace {

using sweep_engine::LoadedTrace;
using sweep_engine::SweepContext;
using sweep_engine::SweepTask;
using sweep_engine::SweepTaskResult;

/// Adds the columns of schema version 3 to a sweep_points table written before it.
void migrate_sweep_points(SQLite::Database& db) {
  std::set<std::string> columns;
  SQLite::Statement info(db, "PRAGMA table_info(sweep_points)");
  while (info.executeStep()) columns.insert(info.getColumn(1).getString());
  for (const auto& [name, type] : results::kSweepPointColumnsV3) {
    if (!columns.contains(std::string(name))) {
      db.exec(fmt::format("ALTER TABLE sweep_points ADD COLUMN {} {}", name, type));
    }
  }
}

/// The run of a sweep: the master's state and loop (docs/SWEEPS.md "How a sweep runs").
SweepOutcome run_sweep_impl(const SweepSpec& spec, const SweepOptions& options,
                            std::shared_ptr<const LoadedTrace> given) {
  const auto start = std::chrono::steady_clock::now();
  // Everything that can be checked is checked before the results database is touched.
  if (options.db.empty()) throw std::runtime_error("sweep: expected a results database path");
  SweepContext context(spec, options);  // resolves the workload points (their errors first)
  if (spec.traces_workload() && std::filesystem::exists(context.store) &&
      !std::filesystem::is_directory(context.store)) {
    throw std::runtime_error(
        fmt::format("{}: trace store: exists and is not a folder (give --trace-store a folder)",
                    context.store.string()));
  }
  const SweepPoints& points = context.points;
  if (given) {
    // Its host times on the base platform, before any work: a measured host needs the trace's
    // host speed, a modeled one costs for every row.
    PlatformHostTimes::of(Platform::parse(context.base).host, given->frames, given->meta,
                          given->name);
    context.workloads[0].trace = given->name;
    context.set_trace(0, given);
  }
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
    migrate_sweep_points(db);
    take_sweep_lock(db, options.db.string(), out.sweep_id);
    SQLite::Statement sweep(db, "INSERT OR REPLACE INTO sweeps VALUES (?, ?, ?, ?, ?, ?)");
    sweep.bind(1, out.sweep_id);
    sweep.bind(2, spec.file);
    sweep.bind(3, spec.base.string());
    sweep.bind(4, given ? given->name : context.store.string());
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

  // Per workload point: whether its trace is there (in the store already, or given).
  enum class TraceState { kMissing, kQueued, kReady, kFailed };
  struct WorkloadState {
    TraceState state = TraceState::kMissing;
    std::string trace_hash, error;
    std::vector<std::size_t> waiting;  ///< points admitted before their trace was ready
  };
  std::vector<WorkloadState> states(context.workloads.size());
  if (given) {
    states[0] = {TraceState::kReady, given->hash, {}, {}};
  } else {
    for (std::size_t w = 0; w < context.workloads.size(); ++w) {
      const std::filesystem::path& file = context.workloads[w].trace;
      if (!std::filesystem::exists(file)) continue;
      const trace::TraceReader reader(file);  // meta and frame count only
      states[w].state = TraceState::kReady;
      states[w].trace_hash = trace_hash(reader.frame_count(), reader.meta());
    }
  }
  const auto record_workload = [&](std::size_t w, const SweepTaskResult* traced) {
    const sweep_engine::Workload& workload = context.workloads[w];
    SQLite::Statement s(db,
                        "INSERT OR REPLACE INTO sweep_workloads VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
    s.bind(1, out.sweep_id);
    s.bind(2, workload.hash);
    s.bind(3, workload.resolved.dump());
    s.bind(4, workload.trace.string());
    s.bind(5, states[w].trace_hash);
    if (states[w].error.empty()) {
      s.bind(6);
    } else {
      s.bind(6, states[w].error);
    }
    if (traced) {
      s.bind(7, traced->seconds);
      s.bind(8, traced->host);
    } else {
      s.bind(7);
      s.bind(8);
    }
    s.exec();
  };

  std::unique_ptr<sweep_engine::SweepExecutor> executor =
      options.distributed ? sweep_engine::make_mpi_executor(context)
                          : std::make_unique<sweep_engine::LocalExecutor>(context, options.jobs);
  struct FinishExecutor {
    sweep_engine::SweepExecutor& executor;
    ~FinishExecutor() { executor.finish(); }
  } finish_executor{*executor};

  std::map<std::size_t, SweepPointResult> finished;
  std::set<std::size_t> claimed;  // points admitted (a search may ask for one twice)
  std::size_t simulations = 0;    // started, toward the limit
  bool limit_reached = false;
  const std::size_t limit =
      options.limit > 0 ? options.limit : std::numeric_limits<std::size_t>::max();
  // A finished point: its run (simulated here, or found in the database) and its row, in one
  // transaction.
  const auto finish = [&](SweepPointResult r, const std::function<void()>& write_run) {
    SQLite::Transaction t(db);
    if (write_run) write_run();
    put_point(db, out.sweep_id, r);
    t.commit();
    new_database.keep = true;
    if (!r.error.empty()) {
      ++out.failed;
    } else {
      (r.computed ? out.computed : out.skipped) += 1;
    }
    if (options.progress) options.progress(finished.size() + 1, out.total, r);
    finished.emplace(r.index, std::move(r));
  };
  std::deque<SweepTask> ready;       // simulations to start
  std::deque<std::size_t> to_trace;  // workload points to trace
  std::size_t in_flight = 0;
  const auto point_result = [&](std::size_t index) {
    SweepPointResult r;
    r.index = index;
    r.parameters = points.at(index).parameters(spec);
    r.workload = context.workloads[context.workload_of(index)].hash;
    return r;
  };
  // A point whose trace is ready: read back from the database, or queued for simulation.
  const auto consider = [&](std::size_t index, std::size_t w) {
    auto platform = std::make_shared<const Platform>(context.platform(index));
    SweepPointResult r = point_result(index);
    r.run_id = run_id_of(fnv1a_hex(platform->to_json().dump()), states[w].trace_hash);
    SQLite::Statement q(db, "SELECT summary_json FROM runs WHERE run_id = ?");
    q.bind(1, r.run_id);
    if (q.executeStep()) {
      evaluate(spec, nlohmann::json::parse(q.getColumn(0).getString()), r);
      q.reset();
      finish(std::move(r), {});
    } else if (simulations >= limit) {
      limit_reached = true;
    } else {
      ++simulations;
      ready.push_back(SweepTask{SweepTask::Kind::kSimulate, w, index, std::move(platform)});
    }
  };
  const auto fail = [&](std::size_t index, std::size_t w) {
    SweepPointResult r = point_result(index);
    r.feasible = false;
    r.metrics = nlohmann::json::object();
    r.error = states[w].error;
    finish(std::move(r), {});
  };
  const auto admit = [&](std::size_t index) {
    if (!claimed.insert(index).second) return;
    const std::size_t w = context.workload_of(index);
    switch (states[w].state) {
      case TraceState::kReady:
        return consider(index, w);
      case TraceState::kFailed:
        return fail(index, w);
      case TraceState::kMissing:
        states[w].state = TraceState::kQueued;
        to_trace.push_back(w);
        [[fallthrough]];
      case TraceState::kQueued:
        states[w].waiting.push_back(index);
    }
  };
  const auto handle = [&](SweepTaskResult r) {
    const std::size_t w = r.task.workload;
    if (r.task.kind == SweepTask::Kind::kTrace) {
      if (options.trace_progress) {
        options.trace_progress(w, context.workloads[w].resolved, &r.error);
      }
      if (r.error.empty()) {
        const trace::TraceReader reader(context.workloads[w].trace);
        states[w].state = TraceState::kReady;
        states[w].trace_hash = trace_hash(reader.frame_count(), reader.meta());
        ++out.traced;
      } else {
        states[w].state = TraceState::kFailed;
        states[w].error = r.error;
      }
      {
        SQLite::Transaction t(db);
        record_workload(w, &r);
        t.commit();
      }
      for (std::size_t index : std::exchange(states[w].waiting, {})) {
        if (r.error.empty()) {
          consider(index, w);
        } else {
          fail(index, w);
        }
      }
      return;
    }
    if (!r.error.empty()) {
      throw std::runtime_error(fmt::format("point {}: {}", r.task.point, r.error));
    }
    SweepPointResult p = point_result(r.task.point);
    p.computed = true;
    if (r.result) {
      p.run_id = run_id_of(r.result->config_hash, r.result->trace_hash);
      evaluate(spec, r.result->to_json(), p);
      finish(std::move(p),
             [&] { write_results(db, *r.result, ResultsWriteOptions{options.per_frame}); });
    } else {
      p.run_id = r.rows.at("run_id").get<std::string>();
      evaluate(spec, r.rows.at("summary"), p);
      finish(std::move(p), [&] { import_run_rows(db, r.rows); });
    }
  };
  // Runs points (indices in the order given) to the end or the limit: traces first, then the
  // simulations of points whose trace is ready; points are admitted lazily, as workers free up,
  // so memory grows with the points finished, not with the grid.
  const auto run_points = [&](std::size_t count,
                              const std::function<std::size_t(std::size_t)>& index_at) {
    // Every workload point the points need is queued for tracing up front.
    for (std::size_t i = 0; spec.traces_workload() && i < count; ++i) {
      const std::size_t w = context.workload_of(index_at(i));
      if (states[w].state == TraceState::kMissing) {
        states[w].state = TraceState::kQueued;
        to_trace.push_back(w);
      }
    }
    std::size_t cursor = 0;
    for (;;) {
      while (executor->has_idle_worker()) {
        if (!to_trace.empty()) {
          executor->start(SweepTask{SweepTask::Kind::kTrace, to_trace.front(), 0, nullptr});
          to_trace.pop_front();
        } else if (!ready.empty()) {
          executor->start(std::move(ready.front()));
          ready.pop_front();
        } else if (cursor < count && !limit_reached) {
          admit(index_at(cursor++));
          continue;
        } else {
          break;
        }
        ++in_flight;
      }
      if (in_flight == 0) {
        if (cursor < count && !limit_reached) continue;
        break;
      }
      SweepTaskResult r = executor->wait();
      --in_flight;
      handle(std::move(r));
    }
  };
  if (spec.nsga2) {
    // The search asks for a generation at a time; a design it asked for before is read from
    // `finished`. The limit stops it (a re-run replays the same generations from the database).
    struct LimitReached {};
    try {
      out.generations = run_nsga2(spec, points, [&](const std::vector<std::size_t>& indices) {
        run_points(indices.size(), [&](std::size_t i) { return indices[i]; });
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
    run_points(points.size(), [](std::size_t i) { return i; });
  }
  executor->finish();
  // Workloads found in the store are recorded too (a resumed sweep lists every trace it used).
  {
    SQLite::Transaction t(db);
    for (std::size_t w = 0; spec.traces_workload() && w < context.workloads.size(); ++w) {
      if (states[w].state == TraceState::kReady) {
        SQLite::Statement has(db,
                              "SELECT 1 FROM sweep_workloads WHERE sweep_id = ? AND workload = ?");
        has.bind(1, out.sweep_id);
        has.bind(2, context.workloads[w].hash);
        if (!has.executeStep()) record_workload(w, nullptr);
      }
    }
    t.commit();
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

}  // namespace

SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options) {
  if (spec.traces_workload()) {
    if (!options.trace.empty()) {
      throw std::runtime_error(fmt::format(
          "{}: --trace: this sweep traces its workload points (workload:), it takes no trace",
          spec.file));
    }
    return run_sweep_impl(spec, options, nullptr);
  }
  const std::filesystem::path trace_path = options.trace.empty() ? spec.trace : options.trace;
  if (trace_path.empty()) {
    throw std::runtime_error(
        fmt::format("{}: trace: no trace (give trace: or --trace)", spec.file));
  }
  return run_sweep_impl(spec, options,
                        std::make_shared<const LoadedTrace>(
                            sweep_engine::load_trace(trace_path, trace_path.string())));
}

SweepOutcome run_sweep(const SweepSpec& spec, const SweepOptions& options,
                       const std::vector<trace::FrameTrace>& frames,
                       const trace::TraceMeta& trace_meta, const std::string& trace_name) {
  if (frames.empty())
    throw std::runtime_error(fmt::format("{}: the trace has no frames", trace_name));
  if (!trace_meta.contains("resolution")) {
    throw std::runtime_error(fmt::format("{}: trace meta has no resolution", trace_name));
  }
  auto trace = std::make_shared<LoadedTrace>();
  trace->frames = frames;
  trace->meta = trace_meta;
  trace->name = trace_name;
  trace->hash = trace_hash(frames.size(), trace_meta);
  return run_sweep_impl(spec, options, std::move(trace));
}

std::string format_sweep(const SweepSpec& spec, const SweepOutcome& o) {
  std::string text =
      fmt::format("sweep      {}: {} points ({} simulated, {} from the database) in {:.2f} s{}\n",
                  o.sweep_id, o.total, o.computed, o.skipped, o.seconds,
                  o.complete ? ""
                             : fmt::format("; stopped by the limit, {} left (re-run to resume)",
                                           o.total - o.points.size()));
  if (spec.traces_workload()) {
    text += fmt::format("workloads  {} traced in this run, {} points failed (no trace)\n", o.traced,
                        o.failed);
  }
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
    if (!r.error.empty()) return line + fmt::format("  error: {}\n", r.error);
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
    // workload and error: results schema 3 (a version-2 database has neither).
    std::set<std::string> columns;
    SQLite::Statement info(db, "PRAGMA table_info(sweep_points)");
    while (info.executeStep()) columns.insert(info.getColumn(1).getString());
    const bool v3 = columns.contains("workload") && columns.contains("error");
    SQLite::Statement q(db, fmt::format("SELECT point, run_id, parameters_json, metrics_json, "
                                        "feasible, pareto{} FROM sweep_points WHERE sweep_id = ? "
                                        "ORDER BY point",
                                        v3 ? ", workload, error" : ""));
    q.bind(1, sweep);
    struct Row {
      std::int64_t point;
      std::string run_id, workload, error;
      nlohmann::json parameters, metrics;
      int feasible, pareto;
    };
    std::vector<Row> points;
    std::vector<std::string> params, metrics;  // the union over the points, in first-seen order
    const auto add_keys = [](std::vector<std::string>& keys, const nlohmann::json& j) {
      for (const auto& [k, v] : j.items()) {
        if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
      }
    };
    bool traced = false;  // a workload sweep: its points' workload and error are columns too
    while (q.executeStep()) {
      Row r{q.getColumn(0).getInt64(),
            q.getColumn(1).getString(),
            v3 ? q.getColumn(6).getString() : std::string(),
            v3 && !q.getColumn(7).isNull() ? q.getColumn(7).getString() : std::string(),
            nlohmann::json::parse(q.getColumn(2).getString()),
            nlohmann::json::parse(q.getColumn(3).getString()),
            q.getColumn(4).getInt(),
            q.getColumn(5).getInt()};
      add_keys(params, r.parameters);
      add_keys(metrics, r.metrics);
      traced = traced || !r.workload.empty();
      points.push_back(std::move(r));
    }
    if (points.empty()) {
      throw std::runtime_error(fmt::format("{}: no sweep named '{}'", db_path.string(), sweep));
    }
    csv = "point,run_id";
    for (const std::string& k : params)
      fmt::format_to(std::back_inserter(csv), ",{}", csv_field(k));
    for (const std::string& k : metrics)
      fmt::format_to(std::back_inserter(csv), ",{}", csv_field(k));
    csv += traced ? ",feasible,pareto,workload,error\n" : ",feasible,pareto\n";
    for (const Row& r : points) {
      fmt::format_to(std::back_inserter(csv), "{},{}", r.point, r.run_id);
      for (const std::string& k : params) {
        fmt::format_to(std::back_inserter(csv), ",{}",
                       csv_field(r.parameters.value(k, std::string())));
      }
      for (const std::string& k : metrics) {
        fmt::format_to(
            std::back_inserter(csv), ",{}",
            r.metrics.contains(k) ? fmt::format("{}", r.metrics[k].get<double>()) : std::string());
      }
      fmt::format_to(std::back_inserter(csv), ",{},{}", r.feasible, r.pareto);
      if (traced) {
        fmt::format_to(std::back_inserter(csv), ",{},{}", r.workload, csv_field(r.error));
      }
      csv += "\n";
    }
    rows = points.size();
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
