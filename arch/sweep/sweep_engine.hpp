#pragma once
// The inside of a sweep run (internal to arch/sweep): what a worker is asked to do, how it does
// it, and where it runs. One master (run_sweep, the process owning the results database) turns
// points into tasks, workload traces first, then the design points whose trace is ready; workers
// execute them: threads of this process (LocalExecutor), and under MPI also the other ranks
// (sweep_mpi.cpp), which run the same SweepContext::execute_* code on their own copy of the spec.
#include <sys/types.h>

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "arch/platform/platform.hpp"
#include "arch/results/schema.hpp"
#include "arch/sweep/sweep.hpp"
#include "arch/system/frontend_study.hpp"
#include "arch/system/system_model.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch::sweep_engine {

/// A trace in memory, as the points simulated on it need it.
struct LoadedTrace {
  std::vector<trace::FrameTrace> frames;
  trace::TraceMeta meta;
  std::string name;  ///< stored with runs (the trace file as the master names it)
  std::string hash;  ///< trace_hash(frames, meta): the runs' trace_hash
};

/// This machine's host name ("unknown" when it has none): lock rows, who traced what.
std::string this_host();

/// Reads a trace file (`name` is what runs record).
LoadedTrace load_trace(const std::filesystem::path& path, const std::string& name);

/// One workload point of the sweep: the given trace (specs with trace:), or a traced one.
struct Workload {
  nlohmann::json resolved;      ///< full parameters (null for a given trace)
  std::string hash;             ///< content hash ("" for a given trace)
  std::filesystem::path trace;  ///< its trace file (in the store for a traced workload)
  std::size_t first_point = 0;  ///< one of its design points (names it in messages)
};

struct SweepTask {
  enum class Kind { kTrace, kSimulate };
  Kind kind = Kind::kSimulate;
  std::size_t workload = 0;  ///< index into SweepContext::workloads
  std::size_t point = 0;     ///< kSimulate: the design point
  /// kSimulate on a local worker: the point's platform (made by the master; remote workers make
  /// it again from `point`).
  std::shared_ptr<const Platform> platform;
};

struct SweepTaskResult {
  SweepTask task;
  std::string error;  ///< kTrace: why the workload could not be traced ("" when it was)
  double seconds = 0;
  std::string host;  ///< where it ran
  /// kSimulate on a local worker: the run's id, summary and rows as values (result_rows and
  /// run_values, made by the worker so that the master only stores them).
  struct LocalRun {
    std::string run_id;
    nlohmann::json summary;
    std::vector<results::TableValues> tables;
  };
  std::shared_ptr<const LocalRun> local_run;
  nlohmann::json rows;  ///< kSimulate on a remote one (export_run_rows)
};

/// What every process of a sweep knows: the spec, the base platform, the workload points, and
/// caches of traces and frontend studies shared by the workers of this process.
class SweepContext {
 public:
  /// Resolves the workload points (bad workload values throw, naming the spec and the key).
  SweepContext(const SweepSpec& spec, const SweepOptions& options);

  const SweepSpec& spec;
  const SweepOptions& options;
  const PlatformSource base;
  const SweepPoints points;
  std::filesystem::path store;  ///< trace store (workload sweeps)
  /// The grid's workload points (by workload index), then the reference workload points of
  /// relative constraints that are not grid points.
  std::vector<Workload> workloads;
  /// Per grid workload point and constraint: the workload index of its reference (relative
  /// constraints; SIZE_MAX for the others).
  std::vector<std::vector<std::size_t>> references;

  /// The workload points a design point needs: its own, then its references.
  std::vector<std::size_t> needed_workloads(std::size_t point) const;

  /// The workload index of a design point.
  std::size_t workload_of(std::size_t point) const;
  /// The point's platform (yaml-cpp is not thread safe: call from one thread at a time).
  Platform platform(std::size_t point) const;

  /// Traces workload `w` into `out` (all or nothing); the error message when it fails.
  std::string execute_trace(std::size_t w, const std::filesystem::path& out) const;
  /// Simulates a point on its workload's trace (loaded once per process).
  SystemResult execute_simulate(const Platform& platform, std::size_t w);
  /// Executes a task on a worker of this process (never throws for a trace task: its failure is
  /// the result's error).
  SweepTaskResult execute_local(const SweepTask& task);

  /// The trace of workload `w`, read from its file by the first worker asking (thread safe).
  std::shared_ptr<const LoadedTrace> trace_of(std::size_t w);
  /// Installs a trace loaded elsewhere (frames in memory, or bytes received over MPI).
  void set_trace(std::size_t w, std::shared_ptr<const LoadedTrace> trace);
  /// Host times already computed on workload `w`'s trace (call before the workers start): its
  /// frontend studies take them when their host is the one they are of.
  void set_known_host_times(std::size_t w, KnownHostTimes known);

 private:
  /// Fills `references` (and adds the reference workload points) for the grid's workloads.
  void add_references(std::size_t grid_workloads);
  std::mutex mutex_;
  std::map<std::size_t, std::shared_future<std::shared_ptr<const LoadedTrace>>> traces_;
  std::map<std::string, std::shared_future<std::shared_ptr<const FrontendStudy>>> studies_;
  std::map<std::string, std::shared_future<std::shared_ptr<const BaselineRuns>>> baselines_;
  std::map<std::size_t, KnownHostTimes> known_host_times_;  ///< by workload; set before workers
};

/// Where tasks run.
class SweepExecutor {
 public:
  virtual ~SweepExecutor() = default;
  /// Whether a task can be started now (a worker takes it now, or, on a local executor, as soon
  /// as one ends its task: one task waits queued).
  virtual bool has_idle_worker() = 0;
  virtual void start(SweepTask task) = 0;
  /// The next finished task (blocks; only called with tasks in flight).
  virtual SweepTaskResult wait() = 0;
  /// Called once when the sweep ends (however it ends): release the workers.
  virtual void finish() {}
};

/// `jobs` threads of this process.
class LocalExecutor : public SweepExecutor {
 public:
  LocalExecutor(SweepContext& context, int jobs);
  ~LocalExecutor() override;
  bool has_idle_worker() override;
  void start(SweepTask task) override;
  SweepTaskResult wait() override;
  /// A finished task if there is one (does not block).
  std::optional<SweepTaskResult> poll();
  void finish() override;

 private:
  void work();
  SweepContext& context_;
  const int jobs_;
  std::mutex mutex_;
  std::condition_variable task_ready_, result_ready_;
  std::deque<SweepTask> tasks_;
  std::deque<SweepTaskResult> results_;
  int busy_ = 0;  ///< tasks started and not yet taken back by wait/poll (at most jobs + 1)
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

/// The MPI executor of rank 0 (sweep_mpi.cpp; throws when edx was built without MPI).
std::unique_ptr<SweepExecutor> make_mpi_executor(SweepContext& context);

/// Traces a resolved workload into `out`, generating its data under <store>/data; "" or the
/// error (the tracer's message).
std::string trace_workload(const WorkloadTracer& tracer, const nlohmann::json& resolved,
                           const std::filesystem::path& out, const std::filesystem::path& store);

/// Traces a resolved workload of hash `hash` (workload_hash) into <store>/<hash>.db: written
/// under <store>/tmp and renamed into place, so the store only ever holds complete traces. ""
/// or the error.
std::string trace_into_store(const WorkloadTracer& tracer, const nlohmann::json& resolved,
                             const std::string& hash, const std::filesystem::path& store);

/// Whether process `pid` of this host is running: it exists (kill(pid, 0)) and is not a zombie
/// (a killed process whose parent has not reaped it, as under an init that never reaps, e.g. in
/// containers; /proc/<pid>/stat's state 'Z').
bool process_running(pid_t pid);

/// Makes `store` ready for traces before any work: a folder (created with its tmp/) that this
/// process can write into, and removes from its tmp/ the traces left by writers that are gone
/// (killed sweeps, MPI ranks, seeds; only files of this host whose process is not running).
/// Throws one line naming the store otherwise ("exists and is not a folder", "cannot create
/// it: ...", "cannot write into it: ..."). Returns the number of files removed.
std::size_t open_trace_store(const std::filesystem::path& store);

/// A task's trace file name while it is written (unique per process and task).
std::filesystem::path temporary_trace_path(const std::filesystem::path& store,
                                           const std::string& hash);

}  // namespace edx::arch::sweep_engine
