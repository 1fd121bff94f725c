// Load-free host times (DESIGN.md; workloads/trace/host_clock.hpp, host_speed.hpp): the same
// small trace made on a quiet machine and while sibling processes keep every core busy records
// the same host times in units of its reference-suite times to within 10 % (a wall clock would
// record about twice as much), and identical modeled host times (arch/host/host_costs.hpp). Also
// the clocks themselves: a thread's CPU time does not advance while it sleeps.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

#include "arch/host/host_model.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/backend_registry.hpp"
#include "workloads/modes/trace_runner.hpp"
#include "workloads/trace/host_clock.hpp"
#include "workloads/trace/host_speed.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;

TEST(HostClock, ThreadCpuTimeDoesNotCountSleep) {
  const std::int64_t thread0 = trace::thread_cpu_ns();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_LT(trace::thread_cpu_ns() - thread0, 5'000'000);
  // Work counts.
  volatile double x = 0;
  const std::int64_t before = trace::thread_cpu_ns();
  for (int i = 0; i < 20'000'000; ++i) x = x + 1e-9 * i;
  EXPECT_GT(trace::thread_cpu_ns() - before, 1'000'000);
}

/// Children that spin until killed, one per core: every core is kept busy and the trace shares
/// one with a spinner, so a wall clock would record about twice its quiet time.
class BusySiblings {
 public:
  BusySiblings() {
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
  ~BusySiblings() {
    for (pid_t pid : children_) kill(pid, SIGKILL);
    for (pid_t pid : children_) waitpid(pid, nullptr, 0);
  }
  std::size_t count() const { return children_.size(); }

 private:
  std::vector<pid_t> children_;
};

/// A trace's host-time totals in units of its own reference-suite times (meta host_speed): the
/// frontend over the suite's frontend part, backend and kernels over its backend part. These
/// ratios are what a platform's host times follow (arch/host/host_model.hpp).
struct Totals {
  double frontend = 0, backend = 0, kernels = 0;
  double suite_frontend_ms = 0, suite_backend_ms = 0;
  /// The platform host times of the op-count model (host.times: modeled, the default).
  arch::PlatformHostTimes modeled;
};

Totals trace_totals(const fs::path& data, const fs::path& out) {
  TraceRunOptions options;
  options.dataset_path = data;
  options.out = out;
  options.make_backend = backend_factory("slam");
  run_trace(options);
  Totals t;
  const trace::TraceReader reader(out);
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  arch::HostConfig host;  // Edx-Car's suite times
  host.frontend_suite_ms = 170.03;
  host.backend_suite_ms = 48.01;
  t.modeled = arch::PlatformHostTimes::of(host, frames, reader.meta(), out.string());
  for (const trace::FrameTrace& f : frames) {
    t.frontend += static_cast<double>(f.frame.frontend_host_ns) * 1e-6;
    t.backend += static_cast<double>(f.frame.backend_host_ns) * 1e-6;
    for (const trace::KernelRecord& k : f.kernels) {
      t.kernels += static_cast<double>(k.host_ns) * 1e-6;
    }
  }
  const trace::HostSpeed speed = trace::host_speed_of(reader.meta(), out.string());
  t.suite_frontend_ms = speed.frontend_ms;
  t.suite_backend_ms = speed.backend_ms;
  t.frontend /= speed.frontend_ms;
  t.backend /= speed.backend_ms;
  t.kernels /= speed.backend_ms;
  return t;
}

TEST(HostClock, TraceHostTimesDoNotMoveWithTheMachinesLoad) {
  const testing::TempDir dir;
  synthetic::GenerateOptions g;
  g.scenario = synthetic::Scenario::kIndoorUnknown;
  g.frames = 40;
  g.resolution = synthetic::Resolution{376, 240};
  g.out = dir.path() / "data";
  synthetic::generate_dataset(g);

  // A first run pays one-time costs (page faults of fresh allocations, lazy initialization):
  // warm up, then three rounds of quiet and busy. This VM's speed moves by 10-20 % over tens of
  // seconds at busy times of its host (docs/MODEL.md), so each round compares a busy trace with
  // the quiet one just before it, and the bar holds for the median round.
  trace_totals(g.out, dir.path() / "warm.db");
  std::vector<double> frontend, backend, kernels;
  double busy_wall_s = 0;
  for (int round = 0; round < 3; ++round) {
    const Totals quiet = trace_totals(g.out, dir.path() / fmt::format("quiet{}.db", round));
    Totals busy;
    {
      const BusySiblings siblings;
      ASSERT_GT(siblings.count(), 0u);
      const auto start = std::chrono::steady_clock::now();
      busy = trace_totals(g.out, dir.path() / fmt::format("busy{}.db", round));
      busy_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    std::printf(
        "[ figures ] round %d, in suite units, quiet: frontend %.2f, backend %.2f, kernels %.2f "
        "(suite %.1f / %.2f ms); busy siblings: frontend %.2f, backend %.2f, kernels %.2f (suite "
        "%.1f / %.2f ms; trace took %.1f s wall)\n",
        round, quiet.frontend, quiet.backend, quiet.kernels, quiet.suite_frontend_ms,
        quiet.suite_backend_ms, busy.frontend, busy.backend, busy.kernels, busy.suite_frontend_ms,
        busy.suite_backend_ms, busy_wall_s);
    // The modeled host times read only the work, which the load does not change: identical.
    EXPECT_EQ(busy.modeled.frontend_ms, quiet.modeled.frontend_ms) << "round " << round;
    EXPECT_EQ(busy.modeled.backend_ms, quiet.modeled.backend_ms) << "round " << round;
    EXPECT_EQ(busy.modeled.kernel_ms, quiet.modeled.kernel_ms) << "round " << round;
    frontend.push_back(busy.frontend / quiet.frontend);
    backend.push_back(busy.backend / quiet.backend);
    kernels.push_back(busy.kernels / quiet.kernels);
  }
  // Issue 17's bar for measured host times (host.times: measured): trace host time over the
  // trace's own suite time moves less than 10 % with the load.
  EXPECT_NEAR(trace::median_of(frontend), 1.0, 0.10);
  EXPECT_NEAR(trace::median_of(backend), 1.0, 0.10);
  EXPECT_NEAR(trace::median_of(kernels), 1.0, 0.10);
  EXPECT_GT(busy_wall_s, 0.0);
}

}  // namespace
}  // namespace edx::modes
