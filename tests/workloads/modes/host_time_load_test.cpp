// Load-free host times (DESIGN.md; workloads/trace/host_clock.hpp): the same small trace made on
// a quiet machine and while sibling processes keep every core busy records about the same host
// times (a wall clock would record about 2.5x as much). Also the clocks themselves: a thread's
// CPU time does not advance while it sleeps.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <vector>

#include "tests/support/temp_dir.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/backend_registry.hpp"
#include "workloads/modes/trace_runner.hpp"
#include "workloads/trace/host_clock.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;

TEST(HostClock, ThreadCpuTimeDoesNotCountSleep) {
  const std::int64_t thread0 = trace::thread_cpu_ns(), process0 = trace::process_cpu_ns();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_LT(trace::thread_cpu_ns() - thread0, 5'000'000);
  EXPECT_LT(trace::process_cpu_ns() - process0, 5'000'000);
  // Work counts.
  volatile double x = 0;
  const std::int64_t before = trace::thread_cpu_ns();
  for (int i = 0; i < 20'000'000; ++i) x = x + 1e-9 * i;
  EXPECT_GT(trace::thread_cpu_ns() - before, 1'000'000);
}

/// Children that spin until killed, two per core: the trace then gets about a third of a core,
/// so a wall clock would record about 2.5x its quiet time.
class BusySiblings {
 public:
  BusySiblings() {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned i = 0; i < 2 * cores; ++i) {
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

struct Totals {
  double frontend_ms = 0, backend_ms = 0, kernels_ms = 0;
};

Totals trace_totals(const fs::path& data, const fs::path& out) {
  TraceRunOptions options;
  options.dataset_path = data;
  options.out = out;
  options.make_backend = backend_factory("slam");
  run_trace(options);
  Totals t;
  for (const trace::FrameTrace& f : trace::TraceReader(out).read_all()) {
    t.frontend_ms += static_cast<double>(f.frame.frontend_host_ns) * 1e-6;
    t.backend_ms += static_cast<double>(f.frame.backend_host_ns) * 1e-6;
    for (const trace::KernelRecord& k : f.kernels) {
      t.kernels_ms += static_cast<double>(k.host_ns) * 1e-6;
    }
  }
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
  // warm up, then quiet, busy, quiet again.
  trace_totals(g.out, dir.path() / "warm.db");
  const Totals quiet1 = trace_totals(g.out, dir.path() / "quiet1.db");
  Totals busy;
  double busy_wall_s = 0;
  {
    const BusySiblings siblings;
    ASSERT_GT(siblings.count(), 0u);
    const auto start = std::chrono::steady_clock::now();
    busy = trace_totals(g.out, dir.path() / "busy.db");
    busy_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const Totals quiet2 = trace_totals(g.out, dir.path() / "quiet2.db");
  const Totals quiet{(quiet1.frontend_ms + quiet2.frontend_ms) / 2,
                     (quiet1.backend_ms + quiet2.backend_ms) / 2,
                     (quiet1.kernels_ms + quiet2.kernels_ms) / 2};
  std::printf(
      "[ figures ] quiet: frontend %.1f ms, backend %.1f ms, kernels %.1f ms; busy siblings: "
      "frontend %.1f ms, backend %.1f ms, kernels %.1f ms (trace took %.1f s wall)\n",
      quiet.frontend_ms, quiet.backend_ms, quiet.kernels_ms, busy.frontend_ms, busy.backend_ms,
      busy.kernels_ms, busy_wall_s);
  // CPU time on this project's 2-core VM varies by up to about +-20 % from run to run even
  // without siblings (no hardware counters in the VM to count instructions instead), and the
  // siblings' cache pressure adds up to about 20 % (measured 2026-11-25: busy / quiet 0.96 - 1.21):
  // the bound is 40 %, against the ~150 % a wall clock would add. The issue-17 bar of 10 % needs
  // the machine-speed reference of docs/TRACE.md's open items.
  EXPECT_NEAR(busy.frontend_ms / quiet.frontend_ms, 1.0, 0.40);
  EXPECT_NEAR(busy.backend_ms / quiet.backend_ms, 1.0, 0.40);
  EXPECT_NEAR(busy.kernels_ms / quiet.kernels_ms, 1.0, 0.40);
  EXPECT_GT(busy_wall_s, 0.0);
}

}  // namespace
}  // namespace edx::modes
