// The workers' side of a sweep: workload points, tracing one, simulating a point on its trace,
// the caches a process keeps, and the thread executor.
#include "arch/sweep/sweep_engine.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <stdexcept>

#include "arch/host/host_model.hpp"
#include "arch/system/result_rows.hpp"
#include "common/input_error.hpp"
#include "common/parallel.hpp"
#include "common/yaml_fields.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {

std::string workload_hash(const nlohmann::json& resolved, const std::string& version) {
  return fnv1a_hex(resolved.dump() + "\nversion=" + version);
}

std::filesystem::path default_trace_store(const std::filesystem::path& db) {
  std::filesystem::path store = db;
  store.replace_extension(".traces");
  return store;
}

namespace sweep_engine {
std::string this_host() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

LoadedTrace load_trace(const std::filesystem::path& path, const std::string& name) {
  const trace::TraceReader reader(path);
  LoadedTrace t;
  t.frames = reader.read_all();
  t.meta = reader.meta();
  t.name = name;
  if (t.frames.empty()) throw std::runtime_error(fmt::format("{}: the trace has no frames", name));
  if (!t.meta.contains("resolution")) {
    throw std::runtime_error(fmt::format("{}: trace meta has no resolution", name));
  }
  t.hash = trace_hash(t.frames.size(), t.meta);
  return t;
}

std::filesystem::path temporary_trace_path(const std::filesystem::path& store,
                                           const std::string& hash) {
  static std::atomic<unsigned> counter{0};
  return store / "tmp" /
         fmt::format("{}-{}-{}-{}.db", hash, this_host(), ::getpid(), counter.fetch_add(1));
}

namespace {

/// A workload's error (key "features") at the spec's line of the value (a workload.* parameter's
/// value of `point`, or the workload: section's), keyed as the spec writes it.
InputError workload_error(const SweepSpec& spec, const SweepPoint& point, const InputError& e) {
  const std::string key = e.key().empty() ? "workload" : "workload." + e.key();
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
    if (spec.parameters[p].key == key) {
      return e.with_key(key).at(parameter_value_place(spec, p, point.choice[p]));
    }
  }
  const auto line = spec.workload_lines.find(e.key());
  return e.with_key(key).at({spec.file, line == spec.workload_lines.end() ? 0 : line->second});
}

/// A design point of workload point `w` (its workload.* values; every platform value the first).
SweepPoint workload_point(const SweepSpec& spec, std::size_t w) {
  SweepPoint point;
  point.choice.assign(spec.parameters.size(), 0);
  for (std::size_t p = spec.workload_parameters; p-- > 0;) {
    point.choice[p] = w % spec.parameters[p].size();
    w /= spec.parameters[p].size();
  }
  return point;
}

}  // namespace

SweepContext::SweepContext(const SweepSpec& spec_in, const SweepOptions& options_in)
    : spec(spec_in),
      options(options_in),
      base(PlatformSource::load(spec_in.base)),
      points(spec_in) {
  if (!spec.traces_workload()) {
    workloads.push_back(Workload{});
    return;
  }
  if (!options.tracer) {
    throw std::runtime_error(fmt::format(
        "{}: workload: this program cannot trace workloads (no tracer given)", spec.file));
  }
  store = options.trace_store.empty() ? default_trace_store(options.db) : options.trace_store;
  // One workload per combination of the workload.* values, in grid order; each resolved (a bad
  // value is an error before any work, naming the parameter).
  std::size_t count = 1;
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) count *= spec.parameters[p].size();
  for (std::size_t w = 0; w < count; ++w) {
    const SweepPoint point = workload_point(spec, w);
    Workload workload;
    try {
      workload.resolved = options.tracer.resolve(point.workload(spec));
    } catch (const InputError& e) {
      throw workload_error(spec, point, e);
    } catch (const std::exception& e) {
      throw InputError({spec.file}, "workload", e.what());
    }
    workload.hash = workload_hash(workload.resolved, options.tracer.version);
    workload.trace = store / (workload.hash + ".db");
    workloads.push_back(std::move(workload));
  }
  add_references(count);
}

void SweepContext::add_references(std::size_t grid_workloads) {
  std::map<std::string, std::size_t> by_hash;
  for (std::size_t w = 0; w < workloads.size(); ++w) by_hash.emplace(workloads[w].hash, w);
  references.assign(grid_workloads, std::vector<std::size_t>(spec.constraints.size(), SIZE_MAX));
  for (std::size_t w = 0; w < grid_workloads; ++w) {
    const SweepPoint point = workload_point(spec, w);
    for (std::size_t c = 0; c < spec.constraints.size(); ++c) {
      const SweepConstraint& constraint = spec.constraints[c];
      if (!constraint.relative()) continue;
      nlohmann::json values = point.workload(spec);
      for (const auto& [key, value] : constraint.reference.items()) values[key] = value;
      Workload reference;
      try {
        reference.resolved = options.tracer.resolve(values);
      } catch (const InputError& e) {
        // Placed at the reference's value when the reference set it, else as the point's own.
        const std::string key = e.key().empty() ? "workload" : "workload." + e.key();
        const auto line = constraint.reference_lines.find(e.key());
        if (line == constraint.reference_lines.end()) throw workload_error(spec, point, e);
        throw e.with_key(fmt::format("constraints[{}].reference.{}", c, key))
            .at({spec.file, line->second});
      }
      reference.hash = workload_hash(reference.resolved, options.tracer.version);
      const auto [it, added] = by_hash.emplace(reference.hash, workloads.size());
      if (added) {
        reference.trace = store / (reference.hash + ".db");
        workloads.push_back(std::move(reference));
      }
      references[w][c] = it->second;
    }
  }
}

std::vector<std::size_t> SweepContext::needed_workloads(std::size_t point) const {
  const std::size_t w = workload_of(point);
  std::vector<std::size_t> needed = {w};
  if (w < references.size()) {
    for (std::size_t r : references[w]) {
      if (r != SIZE_MAX && r != w) needed.push_back(r);
    }
  }
  return needed;
}

std::size_t SweepContext::workload_of(std::size_t point) const {
  return points.at(point).workload_index(spec);
}

Platform SweepContext::platform(std::size_t point) const {
  return sweep_platform(spec, points.at(point), base);
}

}  // namespace sweep_engine

std::filesystem::path traced_workload(const WorkloadTracer& tracer, const nlohmann::json& workload,
                                      const std::filesystem::path& store) {
  const nlohmann::json resolved = tracer.resolve(workload);
  const std::string hash = workload_hash(resolved, tracer.version);
  const std::filesystem::path trace = store / (hash + ".db");
  if (std::filesystem::is_regular_file(trace)) return trace;
  const std::string error = sweep_engine::trace_into_store(tracer, resolved, hash, store);
  if (!error.empty()) {
    throw std::runtime_error(fmt::format("workload {}: {}", workload.dump(), error));
  }
  return trace;
}

std::vector<SeedTrace> trace_seeds(const WorkloadTracer& tracer, const nlohmann::json& workload,
                                   const std::vector<std::uint64_t>& seeds,
                                   const std::filesystem::path& store,
                                   const std::function<void(std::uint64_t seed)>& tracing,
                                   int threads) {
  sweep_engine::open_trace_store(store);
  std::vector<SeedTrace> out;
  std::vector<std::function<void()>> jobs;
  for (std::uint64_t seed : seeds) {
    nlohmann::json w = workload;
    w["seed"] = std::to_string(seed);
    const std::string hash = workload_hash(tracer.resolve(w), tracer.version);
    out.push_back({seed, store / (hash + ".db")});
    if (std::filesystem::is_regular_file(out.back().trace)) continue;
    if (tracing) tracing(seed);
    jobs.emplace_back([&tracer, &store, w] { traced_workload(tracer, w, store); });
  }
  common::run_jobs(jobs, threads);
  return out;
}

std::string seed_group(const WorkloadTracer& tracer, const nlohmann::json& workload) {
  nlohmann::json resolved = tracer.resolve(workload);
  resolved.erase("seed");
  return workload_hash(resolved, tracer.version);
}

nlohmann::json load_workload_file(const std::filesystem::path& path) {
  const std::string where = path.string();
  const YAML::Node root =
      load_yaml_map(read_input_file(path, "workload file"), where, "workload parameters");
  YamlFields fields(root, where, "");
  nlohmann::json workload = nlohmann::json::object();
  for (const auto& item : root) {
    const std::string key = item.first.Scalar();
    if (key == "seed") fields.fail(key, "the seeds are given by --seeds, not in the workload");
    if (!item.second.IsScalar()) fields.fail(key, "expected a scalar value");
    workload[key] = item.second.Scalar();
  }
  return workload;
}

std::vector<std::uint64_t> parse_seed_list(const std::string& text) {
  constexpr std::size_t kMaxSeeds = 1000;
  const auto bad = [&](const std::string& why) {
    return InputError::expected("--seeds", fmt::format("seeds as 1-5, 1,3,7 or 1-3,7 ({})", why),
                                text);
  };
  const auto number = [&](const std::string& part) -> std::uint64_t {
    if (part.empty() || part.size() > 18 ||
        part.find_first_not_of("0123456789") != std::string::npos) {
      throw bad("non-negative integers");
    }
    return std::stoull(part);
  };
  std::vector<std::uint64_t> seeds;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string part = text.substr(begin, comma - begin);
    const std::size_t dash = part.find('-');
    const std::uint64_t first = number(part.substr(0, dash));
    const std::uint64_t last = dash == std::string::npos ? first : number(part.substr(dash + 1));
    if (last < first) throw bad("a range's first seed at most its last");
    if (last - first >= kMaxSeeds) throw bad("at most 1000 seeds");
    for (std::uint64_t seed = first; seed <= last; ++seed) {
      if (std::find(seeds.begin(), seeds.end(), seed) != seeds.end()) throw bad("each seed once");
      seeds.push_back(seed);
      if (seeds.size() > kMaxSeeds) throw bad("at most 1000 seeds");
    }
    begin = comma + 1;
  }
  return seeds;
}

namespace sweep_engine {

std::string SweepContext::execute_trace(std::size_t w, const std::filesystem::path& out) const {
  return trace_workload(options.tracer, workloads.at(w).resolved, out, store);
}

std::string trace_workload(const WorkloadTracer& tracer, const nlohmann::json& resolved,
                           const std::filesystem::path& out, const std::filesystem::path& store) {
  try {
    std::filesystem::create_directories(out.parent_path());
    tracer.trace(resolved, out, store / "data");
    return {};
  } catch (const std::exception& e) {
    return e.what()[0] ? e.what() : "tracing failed";
  }
}

bool process_running(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno != EPERM) return false;
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t paren = text.rfind(')');  // the command name may hold spaces and parentheses
  return paren == std::string::npos || paren + 2 >= text.size() || text[paren + 2] != 'Z';
}

std::size_t open_trace_store(const std::filesystem::path& store) {
  namespace fs = std::filesystem;
  const std::string name = store.string();
  std::error_code ec;
  if (fs::exists(store, ec) && !fs::is_directory(store, ec)) {
    throw std::runtime_error(fmt::format(
        "{}: trace store: exists and is not a folder (give --trace-store a folder)", name));
  }
  const fs::path tmp = store / "tmp";
  if (fs::create_directories(tmp, ec); ec) {
    throw std::runtime_error(
        fmt::format("{}: trace store: cannot create it: {}", name, ec.message()));
  }
  // Writable: a probe file created and removed (permissions alone do not say it: root, a
  // read-only mount).
  const fs::path probe = tmp / fmt::format(".probe-{}-{}", this_host(), ::getpid());
  if (std::FILE* f = std::fopen(probe.c_str(), "w"); f != nullptr) {
    std::fclose(f);
    fs::remove(probe, ec);
  } else {
    throw std::runtime_error(
        fmt::format("{}: trace store: cannot write into it: {}", name, std::strerror(errno)));
  }
  // temporary_trace_path's names: <hash>-<host>-<pid>-<n>.db (the host may hold '-').
  const std::string host = this_host();
  std::size_t removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(tmp, ec)) {
    const std::string file = entry.path().filename().string();
    if (!file.ends_with(".db")) continue;
    const std::string stem = file.substr(0, file.size() - 3);
    const std::size_t last = stem.rfind('-');
    const std::size_t before = last == std::string::npos ? last : stem.rfind('-', last - 1);
    const std::size_t first = stem.find('-');
    if (before == std::string::npos || first >= before) continue;
    if (stem.substr(first + 1, before - first - 1) != host) continue;
    long long pid = 0;
    const std::string pid_text = stem.substr(before + 1, last - before - 1);
    const auto [end, error] =
        std::from_chars(pid_text.data(), pid_text.data() + pid_text.size(), pid);
    if (error != std::errc() || end != pid_text.data() + pid_text.size() || pid <= 0) continue;
    if (static_cast<pid_t>(pid) == ::getpid() || process_running(static_cast<pid_t>(pid))) {
      continue;
    }
    std::error_code ignored;
    removed += fs::remove(entry.path(), ignored) ? 1 : 0;
    for (const char* suffix : {"-journal", "-wal", "-shm"}) {
      fs::remove(entry.path().string() + suffix, ignored);
    }
  }
  return removed;
}

std::string trace_into_store(const WorkloadTracer& tracer, const nlohmann::json& resolved,
                             const std::string& hash, const std::filesystem::path& store) {
  const std::filesystem::path temporary = temporary_trace_path(store, hash);
  const std::filesystem::path target = store / (hash + ".db");
  std::string error = trace_workload(tracer, resolved, temporary, store);
  if (error.empty()) {
    std::error_code ec;
    std::filesystem::rename(temporary, target, ec);
    if (ec) {
      error = fmt::format("{}: cannot move the trace into the store: {}", target.string(),
                          ec.message());
    }
  }
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  return error;
}

namespace {

/// The value of `key` in `cache`, made by `make` once: the first caller makes it while later
/// callers of the same key wait for it (`mutex` guards the map only, not the making).
template <typename Key, typename Value, typename Make>
Value made_once(std::mutex& mutex, std::map<Key, std::shared_future<Value>>& cache, const Key& key,
                const Make& make) {
  std::promise<Value> mine;
  std::shared_future<Value> future;
  bool owner = false;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(key);
    if (it == cache.end()) {
      it = cache.emplace(key, mine.get_future().share()).first;
      owner = true;
    }
    future = it->second;
  }
  if (owner) {
    try {
      mine.set_value(make());
    } catch (...) {
      mine.set_exception(std::current_exception());
    }
  }
  return future.get();
}

}  // namespace

std::shared_ptr<const LoadedTrace> SweepContext::trace_of(std::size_t w) {
  return made_once(mutex_, traces_, w, [&] {
    const Workload& workload = workloads.at(w);
    return std::make_shared<const LoadedTrace>(load_trace(workload.trace, workload.trace.string()));
  });
}

void SweepContext::set_trace(std::size_t w, std::shared_ptr<const LoadedTrace> trace) {
  std::promise<std::shared_ptr<const LoadedTrace>> ready;
  ready.set_value(std::move(trace));
  std::lock_guard<std::mutex> lock(mutex_);
  traces_[w] = ready.get_future().share();
}

void SweepContext::set_known_host_times(std::size_t w, KnownHostTimes known) {
  std::lock_guard<std::mutex> lock(mutex_);
  known_host_times_[w] = std::move(known);
}

SystemResult SweepContext::execute_simulate(const Platform& platform, std::size_t w) {
  const std::shared_ptr<const LoadedTrace> trace = trace_of(w);
  // Frontend studies are shared between points with the same frontend_study_key (computed once
  // per process, by the first worker asking), read in place by each point (not copied). The
  // study and the baseline's runs take the sweep's threads: the workers whose points need them
  // wait for them meanwhile (all of them, when the sweep leaves the frontend alone). An MPI
  // rank runs one task at a time beside the others on the cores: one thread.
  const int threads = options.distributed ? 1 : options.jobs;
  const std::shared_ptr<const FrontendStudy> study =
      made_once(mutex_, studies_, frontend_study_key(platform) + "\ntrace=" + trace->hash, [&] {
        FrontendStudyOptions study_options;
        study_options.threads = threads;
        const auto known = known_host_times_.find(w);  // read only once workers run
        if (known != known_host_times_.end()) study_options.known = &known->second;
        return std::make_shared<const FrontendStudy>(
            study_frontend(platform, trace->frames, trace->meta, trace->name, study_options));
      });
  // So are the CPU baseline's DES runs, by baseline_des_key (after the checks simulate_system
  // makes first: a platform that fails them leaves no runs behind for the others).
  platform.validate();
  check_precision(platform, trace->meta, trace->name);
  SystemSimOptions options;
  options.baseline =
      made_once(mutex_, baselines_, baseline_des_key(platform) + "\ntrace=" + trace->hash, [&] {
        return std::make_shared<const BaselineRuns>(
            run_baseline_des(platform, trace->frames, *study, threads));
      });
  return simulate_system(platform, trace->frames, trace->meta, trace->name, study, options);
}

SweepTaskResult SweepContext::execute_local(const SweepTask& task) {
  const auto start = std::chrono::steady_clock::now();
  SweepTaskResult r;
  r.task = task;
  r.host = this_host();
  if (task.kind == SweepTask::Kind::kTrace) {
    // Written beside the store's files and renamed into place: the store only ever holds
    // complete traces (a killed worker leaves a file in <store>/tmp, never a partial <hash>.db).
    const Workload& workload = workloads.at(task.workload);
    r.error = trace_into_store(options.tracer, workload.resolved, workload.hash, store);
  } else {
    const SystemResult result = execute_simulate(*task.platform, task.workload);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    results::RunRows rows = result_rows(result, options.per_frame);
    auto run = std::make_shared<SweepTaskResult::LocalRun>();
    run->tables = results::run_values(rows);
    run->run_id = std::move(rows.run.run_id);
    run->summary = std::move(rows.run.summary);
    r.local_run = std::move(run);
    return r;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

LocalExecutor::LocalExecutor(SweepContext& context, int jobs)
    : context_(context), jobs_(std::max(1, jobs)) {
  for (int j = 0; j < jobs_; ++j) threads_.emplace_back([this] { work(); });
}

LocalExecutor::~LocalExecutor() { finish(); }

void LocalExecutor::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    stop_ = true;
  }
  task_ready_.notify_all();
  for (std::thread& t : threads_) t.join();
}

bool LocalExecutor::has_idle_worker() {
  std::lock_guard<std::mutex> lock(mutex_);
  // One task more than workers waits queued: a worker that ends a task starts the next at once,
  // while the master stores the one it ended and admits the following point.
  return busy_ < jobs_ + 1;
}

void LocalExecutor::start(SweepTask task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++busy_;
    tasks_.push_back(std::move(task));
  }
  task_ready_.notify_one();
}

void LocalExecutor::work() {
  for (;;) {
    SweepTask task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      task_ready_.wait(lock, [&] { return stop_ || !tasks_.empty(); });
      if (tasks_.empty()) return;  // stopping
      task = std::move(tasks_.front());
      tasks_.pop_front();
    }
    SweepTaskResult r;
    try {
      r = context_.execute_local(task);
    } catch (const std::exception& e) {
      r.task = task;
      r.error = e.what();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      results_.push_back(std::move(r));
    }
    result_ready_.notify_one();
  }
}

SweepTaskResult LocalExecutor::wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  result_ready_.wait(lock, [&] { return !results_.empty(); });
  SweepTaskResult r = std::move(results_.front());
  results_.pop_front();
  --busy_;
  return r;
}

std::optional<SweepTaskResult> LocalExecutor::poll() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (results_.empty()) return std::nullopt;
  SweepTaskResult r = std::move(results_.front());
  results_.pop_front();
  --busy_;
  return r;
}

}  // namespace sweep_engine
}  // namespace edx::arch
