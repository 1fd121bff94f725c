#include "workloads/modes/host_load_study.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "workloads/modes/backend_registry.hpp"
#include "workloads/modes/trace_runner.hpp"
#include "workloads/trace/host_speed.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {

namespace fs = std::filesystem;

BusySiblings::BusySiblings() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned i = 0; i < cores; ++i) {
    const pid_t pid = fork();
    if (pid == 0) {
      volatile unsigned long spin = 0;
      for (;;) spin = spin + 1;
    }
    if (pid > 0) children_.push_back(pid);
  }
}

BusySiblings::~BusySiblings() {
  for (pid_t pid : children_) kill(pid, SIGKILL);
  for (pid_t pid : children_) waitpid(pid, nullptr, 0);
}

HostTimeTotals trace_host_time_totals(const fs::path& dataset, const fs::path& out) {
  TraceRunOptions options;
  options.dataset_path = dataset;
  options.out = out;
  options.make_backend = backend_factory("slam");
  const auto start = std::chrono::steady_clock::now();
  run_trace(options);
  HostTimeTotals t;
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const trace::TraceReader reader(out);
  for (const trace::FrameTrace& f : reader.read_all()) {
    t.frontend += static_cast<double>(f.frame.frontend_host_ns) * 1e-6;
    t.backend += static_cast<double>(f.frame.backend_host_ns) * 1e-6;
    for (const trace::KernelRecord& k : f.kernels)
      t.kernels += static_cast<double>(k.host_ns) * 1e-6;
  }
  const trace::HostSpeed speed = trace::host_speed_of(reader.meta(), out.string());
  t.suite_frontend_ms = speed.frontend_ms;
  t.suite_backend_ms = speed.backend_ms;
  t.frontend /= speed.frontend_ms;
  t.backend /= speed.backend_ms;
  t.kernels /= speed.backend_ms;
  return t;
}

HostLoadStudy run_host_load_study(const fs::path& dataset, const fs::path& work_dir, int rounds) {
  if (rounds < 1) throw std::invalid_argument("host load study: expected rounds >= 1");
  fs::create_directories(work_dir);
  trace_host_time_totals(dataset, work_dir / "warm.db");
  HostLoadStudy study;
  std::vector<double> frontend, backend, kernels, wall;
  for (int i = 0; i < rounds; ++i) {
    HostLoadRound round;
    round.quiet_trace = work_dir / fmt::format("quiet{}.db", i);
    round.busy_trace = work_dir / fmt::format("busy{}.db", i);
    round.quiet = trace_host_time_totals(dataset, round.quiet_trace);
    {
      const BusySiblings siblings;
      if (siblings.count() == 0) throw std::runtime_error("host load study: fork failed");
      round.busy = trace_host_time_totals(dataset, round.busy_trace);
    }
    frontend.push_back(round.frontend_ratio());
    backend.push_back(round.backend_ratio());
    kernels.push_back(round.kernels_ratio());
    wall.push_back(round.wall_ratio());
    study.rounds.push_back(round);
  }
  study.frontend_ratio = trace::median_of(frontend);
  study.backend_ratio = trace::median_of(backend);
  study.kernels_ratio = trace::median_of(kernels);
  study.wall_ratio = trace::median_of(wall);
  return study;
}

}  // namespace edx::modes
