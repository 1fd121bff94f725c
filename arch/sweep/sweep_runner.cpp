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
#include <cmath>
#include <deque>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <thread>
#include <utility>

#include "arch/results/results_db.hpp"
#include "arch/results/schema.hpp"
#include "arch/sweep/search.hpp"
#include "arch/sweep/sweep.hpp"
#include "arch/sweep/sweep_engine.hpp"
#include "arch/system/result_rows.hpp"
#include "arch/system/system_model.hpp"
#include "common/atomic_file.hpp"
#include "workloads/eval/trace_accuracy.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

/// Takes the sweep's lock row (inside the caller's write transaction): one process runs a sweep
/// on a database at a time. A lock held by a live process is refused with a line naming it; a
/// lock left by a process of this host that is gone (killed) is taken over.
void take_sweep_lock(SQLite::Database& db, const std::string& db_name,
                     const std::string& sweep_id) {
  const std::string host = sweep_engine::this_host();
  for (const results::SweepLockRow& lock :
       results::select_rows(db, results::sweep_locks_table(), {"sweep_id = ?1", {sweep_id}, ""})) {
    const auto pid = static_cast<pid_t>(lock.pid);
    const bool alive = lock.host != host || sweep_engine::process_running(pid);
    if (alive && !(lock.host == host && pid == ::getpid())) {
      throw std::runtime_error(fmt::format(
          "{}: sweep '{}' is being run by process {} on {} since {} (wait for it, or delete its "
          "row from sweep_locks if that process is gone)",
          db_name, sweep_id, pid, lock.host, lock.started));
    }
  }
  const std::string now = db.execAndGet("SELECT datetime('now')").getString();
  results::insert_rows(db, results::sweep_locks_table(),
                       {{sweep_id, static_cast<std::int64_t>(::getpid()), host, now}}, true);
}

/// A metric's value in the metrics JSON: null when undefined (NaN).
nlohmann::json metric_json(double v) {
  return std::isnan(v) ? nlohmann::json() : nlohmann::json(v);
}

/// The accelerated variant's bottleneck (isolated run, all frames) of a run summary; "" when the
/// run has no attribution (model analytical).
std::string bottleneck_of(const nlohmann::json& summary) {
  const nlohmann::json::json_pointer where("/accelerated/attribution/isolated/all/bottleneck");
  return summary.contains(where) && summary[where].is_string() ? summary[where].get<std::string>()
                                                               : "";
}

/// Objectives and constraint metrics of a run summary and its trace's accuracy (null when the
/// spec has no accuracy metric); `references[c]`: the accuracy of constraint c's reference
/// workload point (relative constraints). A point with an undefined objective (NaN: an
/// accuracy metric of a mode with too few estimates) is infeasible, as is one whose constrained
/// value is undefined.
void evaluate(const SweepSpec& spec, const nlohmann::json& summary, const nlohmann::json& accuracy,
              const std::vector<const nlohmann::json*>& references, SweepPointResult& r) {
  r.metrics = nlohmann::json::object();
  r.objectives.clear();
  r.constraints.clear();
  r.feasible = true;
  r.bottleneck = bottleneck_of(summary);
  // A metric the summary lacks (a JSON pointer to no number) is the spec's error, at its line.
  const auto metric_at = [&](const std::string& metric, int line, const std::string& key) {
    try {
      return point_metric(summary, accuracy, metric);
    } catch (const std::runtime_error& e) {
      throw InputError({spec.file, line}, key, e.what());
    }
  };
  for (std::size_t i = 0; i < spec.objectives.size(); ++i) {
    const SweepObjective& o = spec.objectives[i];
    r.objectives.push_back(metric_at(o.metric, o.line, fmt::format("objectives[{}]", i)));
    r.metrics[o.metric] = metric_json(r.objectives.back());
    r.feasible = r.feasible && !std::isnan(r.objectives.back());
  }
  for (std::size_t c = 0; c < spec.constraints.size(); ++c) {
    const SweepConstraint& con = spec.constraints[c];
    const double v = metric_at(con.metric, con.line, fmt::format("constraints[{}]", c));
    r.metrics[con.metric] = metric_json(v);
    double bounded = v;
    if (con.relative()) {
      const double reference = accuracy_metric(*references.at(c), con.metric);
      r.metrics[con.metric + "_reference"] = metric_json(reference);
      bounded = v / reference;
    }
    r.constraints.push_back(bounded);
    // NaN compares false: an undefined value is outside every bound.
    r.feasible = r.feasible && bounded >= con.lower() && bounded <= con.upper();
  }
}

/// Stores (or replaces) the rows of `points` in sweep_points.
void put_points(SQLite::Database& db, const std::string& sweep_id,
                const std::vector<SweepPointResult>& points) {
  std::vector<results::SweepPointRow> rows;
  for (const SweepPointResult& r : points) {
    rows.push_back({sweep_id, static_cast<std::int64_t>(r.index), r.run_id, r.parameters, r.metrics,
                    r.feasible, r.pareto, r.workload, r.error, r.bottleneck});
  }
  results::insert_rows(db, results::sweep_points_table(), rows, true);
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

/// Per workload point: whether its trace is there (in the store already, or given).
enum class TraceState { kMissing, kQueued, kReady, kFailed };
struct WorkloadState {
  TraceState state = TraceState::kMissing;
  std::string trace_hash, error;
  std::vector<std::size_t> waiting;  ///< points admitted before their trace was ready
};

/// Everything that can be checked before the results database is touched: the trace store is
/// a folder, and a given trace has host times on the base platform (a measured host needs the
/// trace's host speed, a modeled one costs for every row). Makes the given trace the context's.
void prepare_context(SweepContext& context, const std::shared_ptr<const LoadedTrace>& given) {
  if (context.spec.traces_workload()) sweep_engine::open_trace_store(context.store);
  if (!given) return;
  const Platform base = Platform::parse(context.base);
  // Kept for the points' frontend studies whose host is this one (a sweep that leaves the host
  // alone computes them once, not twice).
  auto times = std::make_shared<const PlatformHostTimes>(
      base.host->host_times(given->frames, given->meta, given->name));
  context.workloads[0].trace = given->name;
  context.set_trace(0, given);
  context.set_known_host_times(0, {component_json(*base.host).dump(), std::move(times)});
}

/// A results database this sweep creates is removed again if the sweep fails before its first
/// point is stored (after that it is kept: a re-run resumes from it).
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
};

std::unique_ptr<SQLite::Database> open_results_database(const std::filesystem::path& path) {
  std::unique_ptr<SQLite::Database> db;
  try {
    db = std::make_unique<SQLite::Database>(path.string(),
                                            SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("{}: cannot open the results database: {}", path.string(), e.what()));
  }
  db->exec("PRAGMA busy_timeout = 5000");
  require_results_database(*db, path.string());
  return db;
}

/// The tables (an older database brought to the current schema), the sweep's lock, its row, and
/// the removal of points of an earlier version of the spec under this name, in the caller's
/// transaction.
void register_sweep_rows(SQLite::Database& db, const SweepSpec& spec, const SweepOptions& options,
                         const std::string& trace, std::size_t points) {
  create_results_tables(db, results::TableGroup::kRun);
  create_results_tables(db, results::TableGroup::kSweep);
  take_sweep_lock(db, options.db.string(), spec.name);
  results::insert_rows(db, results::sweeps_table(),
                       {{spec.name, spec.file, spec.base.string(), trace,
                         static_cast<std::int64_t>(points), spec.to_json()}},
                       true);
  SQLite::Statement stale(db, "DELETE FROM sweep_points WHERE sweep_id = ? AND point >= ?");
  stale.bind(1, spec.name);
  stale.bind(2, static_cast<std::int64_t>(points));
  stale.exec();
}

/// register_sweep_rows in one IMMEDIATE transaction: two processes starting at once are
/// serialized here (the second waits for the first's lock row, then sees it).
void register_sweep(SQLite::Database& db, const SweepSpec& spec, const SweepOptions& options,
                    const std::string& trace, std::size_t points) {
  SQLite::Transaction t(db, SQLite::TransactionBehavior::IMMEDIATE);
  register_sweep_rows(db, spec, options, trace, points);
  t.commit();
}

/// The sweep's lock row goes when its run ends, however it ends (a kill leaves it; see
/// take_sweep_lock).
struct ReleaseLock {
  SQLite::Database& db;
  std::string sweep_id;
  bool released = false;
  /// Drops the lock row now (throws SQLite::Exception when it cannot).
  void release() {
    SQLite::Statement drop(db, "DELETE FROM sweep_locks WHERE sweep_id = ? AND pid = ?");
    drop.bind(1, sweep_id);
    drop.bind(2, static_cast<std::int64_t>(::getpid()));
    drop.exec();
    released = true;
  }
  ~ReleaseLock() {
    try {
      if (!released) release();
    } catch (const SQLite::Exception&) {
    }
  }
};

/// Marks the Pareto front over the feasible points of a complete sweep, and stores the points'
/// flags and the search's convergence.
void store_front(SQLite::Database& db, const SweepSpec& spec, SweepOutcome& out) {
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
  put_points(db, out.sweep_id, out.points);
  SQLite::Statement stale(db, "DELETE FROM sweep_generations WHERE sweep_id = ?");
  stale.bind(1, out.sweep_id);
  stale.exec();
  std::vector<results::SweepGenerationRow> generations;
  for (const SearchGeneration& g : out.generations) {
    generations.push_back({out.sweep_id, static_cast<std::int64_t>(g.generation),
                           static_cast<std::int64_t>(g.evaluations),
                           static_cast<std::int64_t>(g.front_size), g.hypervolume});
  }
  results::insert_rows(db, results::sweep_generations_table(), generations);
  t.commit();
}

/// The master's loop over the points of a sweep whose database is open and locked: traces
/// first, then the simulations of points whose trace is ready, each finished point stored in
/// its own transaction (docs/SWEEPS.md "How a sweep runs").
class SweepMaster {
 public:
  SweepMaster(SweepContext& context, SQLite::Database& db, SweepOutcome& out,
              RemoveNewDatabase& new_database, const std::shared_ptr<const LoadedTrace>& given)
      : spec_(context.spec),
        options_(context.options),
        context_(context),
        db_(db),
        out_(out),
        new_database_(new_database),
        states_(context.workloads.size()),
        limit_(options_.limit > 0 ? options_.limit : std::numeric_limits<std::size_t>::max()) {
    find_traces(given);
    executor_ = options_.distributed
                    ? sweep_engine::make_mpi_executor(context)
                    : std::make_unique<sweep_engine::LocalExecutor>(context, options_.jobs);
  }
  /// Claims this process still holds (a failed or limited run) go with it.
  ~SweepMaster() {
    executor_->finish();
    try {
      SQLite::Statement drop(db_, "DELETE FROM run_claims WHERE pid = ? AND host = ?");
      drop.bind(1, static_cast<std::int64_t>(::getpid()));
      drop.bind(2, host_);
      drop.exec();
    } catch (const SQLite::Exception&) {
    }
  }

  /// Runs every point (a grid or samples) or the search, to the end or the limit; the finished
  /// points go to out.points in point order; returns whether the limit stopped it.
  bool run() {
    if (spec_.nsga2) {
      run_search();
    } else {
      run_points(context_.points.size(), [](std::size_t i) { return i; });
    }
    executor_->finish();
    record_store_workloads();
    for (auto& [index, r] : finished_) out_.points.push_back(std::move(r));
    return limit_reached_;
  }

 private:
  /// Per workload point, whether its trace is there: given, or in the store already.
  void find_traces(const std::shared_ptr<const LoadedTrace>& given) {
    if (given) {
      states_[0] = {TraceState::kReady, given->hash, {}, {}};
      return;
    }
    for (std::size_t w = 0; w < context_.workloads.size(); ++w) {
      const std::filesystem::path& file = context_.workloads[w].trace;
      if (!std::filesystem::exists(file)) continue;
      const trace::TraceReader reader(file);  // meta and frame count only
      states_[w].state = TraceState::kReady;
      states_[w].trace_hash = trace_hash(reader.frame_count(), reader.meta());
    }
  }

  /// Stores workload point `w`'s row (traced: this run traced it, with its time and host).
  void record_workload(std::size_t w, const SweepTaskResult* traced) {
    const sweep_engine::Workload& workload = context_.workloads[w];
    results::SweepWorkloadRow row;
    row.sweep_id = out_.sweep_id;
    row.workload = workload.hash;
    row.workload_json = workload.resolved;
    row.trace = workload.trace.string();
    row.trace_hash = states_[w].trace_hash;
    row.error = states_[w].error;
    if (traced) {
      row.seconds = traced->seconds;
      row.host = traced->host;
    }
    results::insert_rows(db_, results::sweep_workloads_table(), {row}, true);
  }

  /// Workloads found in the store are recorded too (a resumed sweep lists every trace it used).
  void record_store_workloads() {
    if (!spec_.traces_workload()) return;
    SQLite::Transaction t(db_);
    for (std::size_t w = 0; w < context_.workloads.size(); ++w) {
      if (states_[w].state != TraceState::kReady) continue;
      SQLite::Statement has(db_,
                            "SELECT 1 FROM sweep_workloads WHERE sweep_id = ? AND workload = ?");
      has.bind(1, out_.sweep_id);
      has.bind(2, context_.workloads[w].hash);
      if (!has.executeStep()) record_workload(w, nullptr);
    }
    t.commit();
  }

  /// A finished point: its run (simulated here, or found in the database) and its row, in one
  /// transaction.
  void finish(SweepPointResult r, const std::function<void()>& write_run) {
    SQLite::Transaction t(db_);
    if (write_run) write_run();
    put_points(db_, out_.sweep_id, {r});
    t.commit();
    new_database_.keep = true;
    if (!r.error.empty()) {
      ++out_.failed;
    } else {
      (r.computed ? out_.computed : out_.skipped) += 1;
    }
    if (options_.progress) options_.progress(finished_.size() + 1, out_.total, r);
    finished_.emplace(r.index, std::move(r));
  }

  SweepPointResult point_result(std::size_t index) const {
    SweepPointResult r;
    r.index = index;
    r.parameters = context_.points.at(index).parameters(spec_);
    r.workload = context_.workloads[context_.workload_of(index)].hash;
    return r;
  }

  /// Whether a run is stored, or may be simulated by this process.
  enum class RunState { kStored, kClaimed, kBusy };

  /// Looks the run up and, when it is not stored and `claim`, claims it for this process
  /// (run_claims), in one IMMEDIATE transaction, so that two sweeps on the database never both
  /// simulate it: kBusy when another live process of this host holds the claim (that sweep
  /// stores the run; this one waits for it). A claim of a process that is gone is taken over;
  /// one of another host is not honoured (its process cannot be checked): both then simulate
  /// the run, which is stored once. `summary` gets a stored run's summary.
  RunState claim_run(const std::string& run_id, bool claim, nlohmann::json& summary) {
    SQLite::Transaction t(db_, SQLite::TransactionBehavior::IMMEDIATE);
    const std::vector<results::RunRow> stored =
        results::select_rows(db_, results::runs_table(), {"run_id = ?1", {run_id}, ""});
    if (!stored.empty()) {
      summary = stored.front().summary;
      return RunState::kStored;
    }
    if (!claim) return RunState::kClaimed;  // the limit stops the sweep before it simulates
    for (const results::RunClaimRow& c :
         results::select_rows(db_, results::run_claims_table(), {"run_id = ?1", {run_id}, ""})) {
      const auto pid = static_cast<pid_t>(c.pid);
      if (c.host == host_ && pid != ::getpid() && sweep_engine::process_running(pid)) {
        return RunState::kBusy;
      }
    }
    const std::string now = db_.execAndGet("SELECT datetime('now')").getString();
    results::insert_rows(
        db_, results::run_claims_table(),
        {{out_.sweep_id, run_id, static_cast<std::int64_t>(::getpid()), host_, now}}, true);
    t.commit();
    return RunState::kClaimed;
  }

  /// This process's claim on a run, removed in the caller's transaction (the run is stored).
  void drop_claim(const std::string& run_id) {
    SQLite::Statement drop(db_, "DELETE FROM run_claims WHERE run_id = ? AND pid = ? AND host = ?");
    drop.bind(1, run_id);
    drop.bind(2, static_cast<std::int64_t>(::getpid()));
    drop.bind(3, host_);
    drop.exec();
  }

  /// A point whose trace is ready: read back from the database, queued for simulation, or
  /// waiting for another sweep that is simulating its run.
  void consider(std::size_t index, std::size_t w) {
    auto platform = std::make_shared<const Platform>(context_.platform(index));
    SweepPointResult r = point_result(index);
    r.run_id = run_id_of(fnv1a_hex(platform->to_json().dump()), states_[w].trace_hash);
    nlohmann::json summary;
    switch (claim_run(r.run_id, simulations_ < limit_, summary)) {
      case RunState::kStored:
        evaluate_point(summary, r);
        finish(std::move(r), {});
        return;
      case RunState::kBusy:
        elsewhere_.push_back({index, w});
        return;
      case RunState::kClaimed:
        break;
    }
    if (simulations_ >= limit_) {
      limit_reached_ = true;
    } else {
      ++simulations_;
      ready_.push_back(SweepTask{SweepTask::Kind::kSimulate, w, index, std::move(platform)});
    }
  }

  /// Points whose run another sweep is simulating, considered again after a pause: each is then
  /// stored (evaluated from the database), or its claim is gone (simulated here).
  void wait_for_other_sweeps() {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (const auto& [index, w] : std::exchange(elsewhere_, {})) consider(index, w);
  }

  /// The accuracy of workload point `w`'s trace (computed once, from the trace).
  const nlohmann::json& accuracy_of(std::size_t w) {
    auto it = accuracy_.find(w);
    if (it == accuracy_.end()) {
      const std::shared_ptr<const LoadedTrace> trace = context_.trace_of(w);
      it = accuracy_.emplace(w, eval::trace_accuracy(trace->frames, trace->meta).to_json()).first;
    }
    return it->second;
  }

  /// Objectives, constraints and feasibility of a point from its run summary (and, when the
  /// spec asks for accuracy, its trace's accuracy and its references').
  void evaluate_point(const nlohmann::json& summary, SweepPointResult& r) {
    static const nlohmann::json kNone;
    if (!spec_.needs_accuracy()) return evaluate(spec_, summary, kNone, {}, r);
    const std::size_t w = context_.workload_of(r.index);
    std::vector<const nlohmann::json*> references(spec_.constraints.size(), nullptr);
    for (std::size_t c = 0; c < references.size(); ++c) {
      if (spec_.constraints[c].relative()) {
        references[c] = &accuracy_of(context_.references.at(w).at(c));
      }
    }
    evaluate(spec_, summary, accuracy_of(w), references, r);
  }

  /// A point whose workload (or a reference's) could not be traced: stored with that error,
  /// infeasible.
  void fail(std::size_t index, std::size_t w) {
    SweepPointResult r = point_result(index);
    r.feasible = false;
    r.metrics = nlohmann::json::object();
    r.constraints.assign(spec_.constraints.size(), std::numeric_limits<double>::quiet_NaN());
    r.objectives.assign(spec_.objectives.size(), std::numeric_limits<double>::quiet_NaN());
    r.error = w == context_.workload_of(index)
                  ? states_[w].error
                  : fmt::format("the reference workload point: {}", states_[w].error);
    finish(std::move(r), {});
  }

  void admit(std::size_t index) {
    if (!claimed_.insert(index).second) return;
    proceed(index);
  }

  /// Considers a point once every workload point it needs (its own, its references) is traced;
  /// until then it waits on the first that is not (queued for tracing if it was missing).
  void proceed(std::size_t index) {
    for (std::size_t w : context_.needed_workloads(index)) {
      switch (states_[w].state) {
        case TraceState::kReady:
          continue;
        case TraceState::kFailed:
          return fail(index, w);
        case TraceState::kMissing:
          states_[w].state = TraceState::kQueued;
          to_trace_.push_back(w);
          [[fallthrough]];
        case TraceState::kQueued:
          states_[w].waiting.push_back(index);
          return;
      }
    }
    consider(index, context_.workload_of(index));
  }

  /// A traced workload point: recorded, and its waiting points considered (or failed).
  void handle_trace(SweepTaskResult& r) {
    const std::size_t w = r.task.workload;
    if (options_.trace_progress) {
      options_.trace_progress(w, context_.workloads[w].resolved, &r.error);
    }
    if (r.error.empty()) {
      const trace::TraceReader reader(context_.workloads[w].trace);
      states_[w].state = TraceState::kReady;
      states_[w].trace_hash = trace_hash(reader.frame_count(), reader.meta());
      ++out_.traced;
    } else {
      states_[w].state = TraceState::kFailed;
      states_[w].error = r.error;
    }
    {
      SQLite::Transaction t(db_);
      record_workload(w, &r);
      t.commit();
    }
    for (std::size_t index : std::exchange(states_[w].waiting, {})) proceed(index);
  }

  /// A simulated point: its run's rows (local: the result; remote: rows exported) and its row.
  void handle_simulation(SweepTaskResult& r) {
    if (!r.error.empty()) {
      throw std::runtime_error(fmt::format("point {}: {}", r.task.point, r.error));
    }
    SweepPointResult p = point_result(r.task.point);
    p.computed = true;
    if (r.local_run) {
      // The rows hold the run's summary: evaluated from them, it is built once.
      const SweepTaskResult::LocalRun& run = *r.local_run;
      p.run_id = run.run_id;
      evaluate_point(run.summary, p);
      const std::string run_id = p.run_id;
      finish(std::move(p), [&] {
        write_results(db_, run.run_id, run.tables);
        drop_claim(run_id);
      });
    } else {
      p.run_id = r.rows.at("run_id").get<std::string>();
      evaluate_point(r.rows.at("summary"), p);
      const std::string run_id = p.run_id;
      finish(std::move(p), [&] {
        import_run_rows(db_, r.rows);
        drop_claim(run_id);
      });
    }
  }

  /// Starts tasks while a worker is idle (traces first, then ready simulations, then admitting
  /// the next point at `cursor`, whose task, if any, starts next).
  void start_tasks(std::size_t count, const std::function<std::size_t(std::size_t)>& index_at,
                   std::size_t& cursor) {
    while (executor_->has_idle_worker()) {
      if (!to_trace_.empty()) {
        executor_->start(SweepTask{SweepTask::Kind::kTrace, to_trace_.front(), 0, nullptr});
        to_trace_.pop_front();
      } else if (!ready_.empty()) {
        executor_->start(std::move(ready_.front()));
        ready_.pop_front();
      } else if (cursor < count && !limit_reached_) {
        admit(index_at(cursor++));
        continue;
      } else {
        return;
      }
      ++in_flight_;
    }
  }

  /// Runs points (indices in the order given) to the end or the limit; points are admitted
  /// lazily, as workers free up, so memory grows with the points finished, not with the grid.
  void run_points(std::size_t count, const std::function<std::size_t(std::size_t)>& index_at) {
    // Every workload point the points need is queued for tracing up front.
    for (std::size_t i = 0; spec_.traces_workload() && i < count; ++i) {
      for (std::size_t w : context_.needed_workloads(index_at(i))) {
        if (states_[w].state == TraceState::kMissing) {
          states_[w].state = TraceState::kQueued;
          to_trace_.push_back(w);
        }
      }
    }
    std::size_t cursor = 0;
    for (;;) {
      start_tasks(count, index_at, cursor);
      if (in_flight_ == 0) {
        if (cursor < count && !limit_reached_) continue;
        if (!elsewhere_.empty()) {
          wait_for_other_sweeps();
          continue;
        }
        break;
      }
      SweepTaskResult r = executor_->wait();
      --in_flight_;
      if (r.task.kind == SweepTask::Kind::kTrace) {
        handle_trace(r);
      } else {
        handle_simulation(r);
      }
    }
  }

  /// The search asks for a generation at a time; a design it asked for before is read from
  /// finished_. The limit stops it (a re-run replays the same generations from the database).
  void run_search() {
    struct LimitReached {};
    try {
      out_.generations =
          run_nsga2(spec_, context_.points, [&](const std::vector<std::size_t>& indices) {
            run_points(indices.size(), [&](std::size_t i) { return indices[i]; });
            if (limit_reached_) throw LimitReached{};
            std::vector<DesignFitness> fitness;
            for (std::size_t index : indices) {
              const SweepPointResult& r = finished_.at(index);
              fitness.push_back(DesignFitness{r.objectives, r.constraints, r.feasible});
            }
            return fitness;
          });
    } catch (const LimitReached&) {
    }
  }

  const SweepSpec& spec_;
  const SweepOptions& options_;
  SweepContext& context_;
  SQLite::Database& db_;
  SweepOutcome& out_;
  RemoveNewDatabase& new_database_;
  std::vector<WorkloadState> states_;
  std::unique_ptr<sweep_engine::SweepExecutor> executor_;
  std::map<std::size_t, SweepPointResult> finished_;
  std::map<std::size_t, nlohmann::json> accuracy_;  // by workload index
  std::set<std::size_t> claimed_;  // points admitted (a search may ask for one twice)
  std::size_t simulations_ = 0;    // started, toward the limit
  const std::size_t limit_;
  bool limit_reached_ = false;
  std::deque<SweepTask> ready_;       // simulations to start
  std::deque<std::size_t> to_trace_;  // workload points to trace
  std::size_t in_flight_ = 0;
  std::vector<std::pair<std::size_t, std::size_t>> elsewhere_;  // (point, workload) waiting
  const std::string host_ = sweep_engine::this_host();
};

/// The run of a sweep (docs/SWEEPS.md "How a sweep runs"): checks, the database opened and
/// locked, the master's loop, the Pareto front of a complete sweep.
SweepOutcome run_sweep_impl(const SweepSpec& spec, const SweepOptions& options,
                            std::shared_ptr<const LoadedTrace> given) {
  const auto start = std::chrono::steady_clock::now();
  if (options.db.empty()) throw std::runtime_error("sweep: expected a results database path");
  SweepContext context(spec, options);  // resolves the workload points (their errors first)
  prepare_context(context, given);
  SweepOutcome out;
  out.sweep_id = spec.name;
  // A search evaluates at most its population in each generation and the initial one.
  const std::size_t points = context.points.size();
  out.total = spec.nsga2 ? std::min(points, spec.population * (spec.generations + 1)) : points;

  common::require_regular_output(options.db, "results database");
  const std::string trace = given ? given->name : context.store.string();
  // A new database appears complete, with this sweep's lock already in it, and never replaces
  // one another process created meanwhile (create_results_database): a sweep refused by that
  // lock never created the file, so it never removes it.
  const bool created = create_results_database(options.db, [&](SQLite::Database& db) {
    register_sweep_rows(db, spec, options, trace, points);
  });
  RemoveNewDatabase new_database{options.db, !created};
  const std::unique_ptr<SQLite::Database> db = open_results_database(options.db);
  // SQLite's own messages ("database or disk is full", "disk I/O error") name no file.
  try {
    register_sweep(*db, spec, options, trace, points);
    ReleaseLock release_lock{*db, out.sweep_id};
    // WAL with synchronous = NORMAL: a commit is not fsynced, but survives the process being
    // killed (only a power cut can lose the last points; the file stays consistent). Set once
    // the sweep's lock is held, so that a refused sweep leaves the file as it was.
    db->exec("PRAGMA journal_mode = WAL");
    db->exec("PRAGMA synchronous = NORMAL");

    bool limit_reached = false;
    {
      SweepMaster master(context, *db, out, new_database, given);
      limit_reached = master.run();
    }
    out.complete = spec.nsga2 ? !limit_reached : out.points.size() == points;
    if (out.complete) store_front(*db, spec, out);
    // The points into the database file itself, flushed to the disk, the WAL emptied: a write
    // or sync that fails here is an error (closing checkpoints too, but ignores failures).
    release_lock.release();
    db->exec("PRAGMA wal_checkpoint(TRUNCATE)");
  } catch (const SQLite::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}: cannot write the sweep's results: {}", options.db.string(), e.what()));
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
    for (double v : r.objectives) {
      line += std::isnan(v) ? fmt::format(" {:>14}", "-") : fmt::format(" {:>14.4g}", v);
    }
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

/// A sweep's points as CSV: point, run_id, a column per parameter and per metric (the union over
/// the points, in first-seen order), feasible, pareto, and for a workload sweep workload, error.
std::string sweep_points_csv(SQLite::Database& db, const std::string& db_name,
                             const std::string& sweep, std::size_t& rows) {
  if (!db.tableExists(results::sweep_points_table().spec.name)) {
    throw std::runtime_error(fmt::format("{}: no sweeps in this database", db_name));
  }
  const std::vector<results::SweepPointRow> points =
      results::select_rows(db, results::sweep_points_table(), {"sweep_id = ?1", {sweep}, "point"});
  if (points.empty()) {
    throw std::runtime_error(fmt::format("{}: no sweep named '{}'", db_name, sweep));
  }
  std::vector<std::string> params, metrics;
  const auto add_keys = [](std::vector<std::string>& keys, const nlohmann::json& j) {
    for (const auto& [k, v] : j.items()) {
      if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    }
  };
  bool traced = false;  // a workload sweep: its points' workload and error are columns too
  for (const results::SweepPointRow& p : points) {
    add_keys(params, p.parameters);
    add_keys(metrics, p.metrics);
    traced = traced || !p.workload.empty();
  }
  std::string csv = "point,run_id";
  for (const std::string& k : params)
    fmt::format_to(std::back_inserter(csv), ",{}", results::csv_field(k));
  for (const std::string& k : metrics)
    fmt::format_to(std::back_inserter(csv), ",{}", results::csv_field(k));
  csv += traced ? ",feasible,pareto,workload,error\n" : ",feasible,pareto\n";
  for (const results::SweepPointRow& p : points) {
    fmt::format_to(std::back_inserter(csv), "{},{}", p.point, p.run_id);
    for (const std::string& k : params) {
      fmt::format_to(std::back_inserter(csv), ",{}",
                     results::csv_field(p.parameters.value(k, std::string())));
    }
    for (const std::string& k : metrics) {
      fmt::format_to(std::back_inserter(csv), ",{}",
                     p.metrics.contains(k) && p.metrics[k].is_number()
                         ? fmt::format("{}", p.metrics[k].get<double>())
                         : "");
    }
    fmt::format_to(std::back_inserter(csv), ",{},{}", static_cast<int>(p.feasible),
                   static_cast<int>(p.pareto));
    if (traced) {
      fmt::format_to(std::back_inserter(csv), ",{},{}", p.workload, results::csv_field(p.error));
    }
    csv += "\n";
  }
  rows = points.size();
  return csv;
}

/// A declared table of the database as CSV (its declared columns; those it lacks are empty).
std::string table_csv(SQLite::Database& db, const std::string& db_name, const std::string& table,
                      std::size_t& rows) {
  std::set<std::string> tables;
  SQLite::Statement t(db, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name");
  while (t.executeStep()) tables.insert(t.getColumn(0).getString());
  if (!tables.contains(table)) {
    throw std::runtime_error(fmt::format("{}: --table: no table '{}' (tables: {})", db_name, table,
                                         fmt::join(tables, ", ")));
  }
  const results::TableSpec* spec = results::find_table(table);
  if (!spec) {
    std::vector<std::string> declared;
    for (const results::TableSpec* d : results::all_tables()) declared.push_back(d->name);
    throw std::runtime_error(fmt::format("{}: --table: '{}' is not a results table ({})", db_name,
                                         table, fmt::join(declared, ", ")));
  }
  const std::vector<results::ValueRow> values = results::select_values(db, *spec);
  rows = values.size();
  return results::table_csv(*spec, values);
}

std::size_t export_csv_from(const std::filesystem::path& db_path, const std::string& table,
                            const std::string& sweep, const std::filesystem::path& out) {
  const std::unique_ptr<SQLite::Database> opened = results::open_for_reading(db_path);
  SQLite::Database& db = *opened;
  if (db.tableExists("runs")) {  // a results database (a trace's tables are exported as they are)
    results::check_schema_version(db.execAndGet("PRAGMA user_version").getInt(), db_path.string());
  }
  std::size_t rows = 0;
  const std::string csv = sweep.empty() ? table_csv(db, db_path.string(), table, rows)
                                        : sweep_points_csv(db, db_path.string(), sweep, rows);
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
