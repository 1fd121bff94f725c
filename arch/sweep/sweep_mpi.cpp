// Sweeps over MPI ranks (distributed.hpp): rank 0's executor and the other ranks' work loop.
//
// Protocol: one tag, each message a CBOR-encoded JSON object.
//   worker -> 0  {type: ready}                                   once, at start
//   0 -> worker  {type: task, kind: trace | simulate, workload, point, trace?: bytes}
//                trace: the trace file of the workload, sent with the first task on it to a rank
//                that does not hold it yet
//   worker -> 0  {type: result, kind, workload, point, error, seconds, host,
//                 trace?: bytes (a traced workload), rows?: export_run_rows + summary}
//   0 -> worker  {type: stop}
// Every wait polls (MPI_Iprobe, then a sleep of 0.2 ms) instead of blocking in MPI_Recv, whose
// busy polling would take a core from the workers of the same machine.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <thread>

#include "arch/results/results_db.hpp"
#include "arch/sweep/distributed.hpp"
#include "arch/sweep/sweep_engine.hpp"
#include "arch/system/result_rows.hpp"
#include "common/atomic_file.hpp"

#ifdef EDX_HAVE_MPI
#include <mpi.h>
#endif

namespace edx::arch {

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

namespace {

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read", path.string()));
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out.flush()) throw std::runtime_error(fmt::format("{}: cannot write", path.string()));
}

}  // namespace

#ifdef EDX_HAVE_MPI

bool built_with_mpi() { return true; }

namespace {

constexpr int kTag = 17;

void send(int rank, const nlohmann::json& message) {
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(message);
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, rank, kTag, MPI_COMM_WORLD);
}

/// A message if one is waiting (from `source`, or any rank): its sender and content.
std::optional<std::pair<int, nlohmann::json>> try_receive(int source = MPI_ANY_SOURCE) {
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(source, kTag, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kTag, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return std::make_pair(status.MPI_SOURCE, nlohmann::json::from_cbor(bytes));
}

std::pair<int, nlohmann::json> receive(int source = MPI_ANY_SOURCE) {
  for (;;) {
    if (auto m = try_receive(source)) return std::move(*m);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

/// Rank 0's executor: one worker thread of its own, and the other ranks.
class MpiExecutor : public sweep_engine::SweepExecutor {
 public:
  explicit MpiExecutor(sweep_engine::SweepContext& context)
      : context_(context), local_(context, 1) {
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    ranks_.resize(static_cast<std::size_t>(size_));
  }
  ~MpiExecutor() override { finish(); }

  bool has_idle_worker() override {
    pump();
    if (local_.has_idle_worker()) return true;
    for (int r = 1; r < size_; ++r)
      if (ranks_[r].waiting) return true;
    return false;
  }

  void start(sweep_engine::SweepTask task) override {
    pump();
    for (int r = 1; r < size_; ++r) {
      if (!ranks_[r].waiting) continue;
      nlohmann::json message = {
          {"type", "task"},
          {"kind", task.kind == sweep_engine::SweepTask::Kind::kTrace ? "trace" : "simulate"},
          {"workload", task.workload},
          {"point", task.point}};
      if (task.kind == sweep_engine::SweepTask::Kind::kSimulate &&
          !ranks_[r].holds.contains(task.workload)) {
        message["trace"] =
            nlohmann::json::binary(read_bytes(context_.workloads.at(task.workload).trace));
        ranks_[r].holds.insert(task.workload);
      }
      send(r, message);
      ranks_[r].waiting = false;
      ranks_[r].task = std::move(task);
      return;
    }
    local_.start(std::move(task));
  }

  sweep_engine::SweepTaskResult wait() override {
    for (;;) {
      pump();
      if (!results_.empty()) {
        sweep_engine::SweepTaskResult r = std::move(results_.front());
        results_.pop_front();
        return r;
      }
      if (auto r = local_.poll()) return std::move(*r);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }

  void finish() override {
    if (finished_) return;
    finished_ = true;
    local_.finish();
    // Every rank gets its stop once it has asked for work (a task still running is waited for
    // and its result dropped: the sweep is over).
    for (int r = 1; r < size_; ++r) {
      while (!ranks_[r].waiting) {
        const auto [source, message] = receive(r);
        (void)source;
        ranks_[r].waiting =
            message.value("type", "") == "ready" || message.value("type", "") == "result";
      }
      send(r, {{"type", "stop"}});
    }
  }

 private:
  struct RankState {
    bool waiting = false;
    std::set<std::size_t> holds;  ///< workloads whose trace the rank has
    sweep_engine::SweepTask task;
  };

  /// Takes every message waiting: ready ranks, and results (a traced workload's file is put in
  /// the store here, renamed into place when complete).
  void pump() {
    while (auto m = try_receive()) {
      auto& [rank, message] = *m;
      RankState& state = ranks_.at(static_cast<std::size_t>(rank));
      state.waiting = true;
      if (message.value("type", "") != "result") continue;
      sweep_engine::SweepTaskResult r;
      r.task = state.task;
      r.error = message.value("error", "");
      r.seconds = message.value("seconds", 0.0);
      r.host = message.value("host", "");
      if (r.task.kind == sweep_engine::SweepTask::Kind::kTrace) {
        if (r.error.empty()) {
          const sweep_engine::Workload& w = context_.workloads.at(r.task.workload);
          const std::filesystem::path temporary =
              sweep_engine::temporary_trace_path(context_.store, w.hash);
          write_bytes(temporary, message.at("trace").get_binary());
          std::filesystem::rename(temporary, w.trace);
          state.holds.insert(r.task.workload);
        }
      } else if (r.error.empty()) {
        r.rows = std::move(message.at("rows"));
      }
      results_.push_back(std::move(r));
    }
  }

  sweep_engine::SweepContext& context_;
  sweep_engine::LocalExecutor local_;
  int size_ = 1;
  std::vector<RankState> ranks_;
  std::deque<sweep_engine::SweepTaskResult> results_;
  bool finished_ = false;
};

}  // namespace

MpiSession::MpiSession() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    MPI_Finalize();
    throw std::runtime_error("MPI: the library does not support MPI_THREAD_FUNNELED");
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

void MpiSession::abort(int code) const {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

void serve_sweep(const SweepSpec& spec, const SweepOptions& options) {
  sweep_engine::SweepContext context(spec, options);
  if (!spec.traces_workload())
    context.workloads[0].trace = options.trace.empty() ? spec.trace : options.trace;
  // A trace file received or written here: loaded, then removed (the store is rank 0's).
  const auto install = [&](std::size_t w, const std::filesystem::path& file) {
    const sweep_engine::Workload& workload = context.workloads.at(w);
    context.set_trace(w, std::make_shared<const sweep_engine::LoadedTrace>(
                             sweep_engine::load_trace(file, workload.trace.string())));
  };
  send(0, {{"type", "ready"}});
  for (;;) {
    const auto [source, task] = receive(0);
    (void)source;
    if (task.value("type", "") == "stop") return;
    const auto start = std::chrono::steady_clock::now();
    const std::size_t w = task.at("workload").get<std::size_t>();
    nlohmann::json result = {{"type", "result"},
                             {"kind", task.at("kind")},
                             {"workload", w},
                             {"point", task.at("point")},
                             {"host", sweep_engine::this_host()}};
    const std::filesystem::path temporary = sweep_engine::temporary_trace_path(
        context.store.empty() ? std::filesystem::temp_directory_path() / "edx-sweep"
                              : context.store,
        context.workloads.at(w).hash.empty() ? "trace" : context.workloads.at(w).hash);
    try {
      if (task.at("kind") == "trace") {
        const std::string error = context.execute_trace(w, temporary);
        result["error"] = error;
        if (error.empty()) {
          result["trace"] = nlohmann::json::binary(read_bytes(temporary));
          install(w, temporary);
        }
      } else {
        if (task.contains("trace")) {
          write_bytes(temporary, task.at("trace").get_binary());
          install(w, temporary);
        }
        const Platform platform = context.platform(task.at("point").get<std::size_t>());
        const SystemResult run = context.execute_simulate(platform, w);
        nlohmann::json rows = export_run_rows(result_rows(run, options.per_frame));
        rows["summary"] = run.to_json();
        result["rows"] = std::move(rows);
        result["error"] = "";
      }
    } catch (const std::exception& e) {
      result["error"] = e.what();
    }
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    result["seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    send(0, result);
  }
}

namespace sweep_engine {
std::unique_ptr<SweepExecutor> make_mpi_executor(SweepContext& context) {
  return std::make_unique<MpiExecutor>(context);
}
}  // namespace sweep_engine

#else  // without MPI

bool built_with_mpi() { return false; }

namespace {
[[noreturn]] void no_mpi() {
  throw std::runtime_error(
      "this edx was built without MPI (install libopenmpi-dev and rebuild to run under mpirun)");
}
}  // namespace

MpiSession::MpiSession() { no_mpi(); }
MpiSession::~MpiSession() = default;
void MpiSession::abort(int code) const { std::exit(code); }
void serve_sweep(const SweepSpec&, const SweepOptions&) { no_mpi(); }

namespace sweep_engine {
std::unique_ptr<SweepExecutor> make_mpi_executor(SweepContext&) { no_mpi(); }
}  // namespace sweep_engine

#endif

}  // namespace edx::arch
