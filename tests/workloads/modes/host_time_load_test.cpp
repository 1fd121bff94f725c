// Load-free host times (DESIGN.md; workloads/trace/host_clock.hpp, host_speed.hpp): the same
// small trace made on a quiet machine and while sibling processes keep every core busy
// (workloads/modes/host_load_study.hpp) gives identical modeled host times
// (arch/host/host_costs.hpp), and measured host times in units of its reference-suite times
// that move at most half as far as a wall clock does. Also the clocks themselves: a thread's
// CPU time does not advance while it sleeps.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "arch/host/host_processor.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/modes/host_load_study.hpp"
#include "workloads/trace/host_clock.hpp"
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

/// The platform host times of the op-count model (host.times: modeled, the default) of a trace,
/// on Edx-Car's host.
arch::PlatformHostTimes modeled_times(const fs::path& trace_file) {
  const trace::TraceReader reader(trace_file);
  const auto host =  // Edx-Car's suite times
      arch::make_host_processor("suite_scaled",
                                "{frontend_suite_ms: 170.03, backend_suite_ms: 48.01}");
  return host->host_times(reader.read_all(), reader.meta(), trace_file.string());
}

TEST(HostClock, TraceHostTimesDoNotMoveWithTheMachinesLoad) {
  const testing::TempDir dir;
  synthetic::GenerateOptions g;
  g.scenario = synthetic::Scenario::kIndoorUnknown;
  g.frames = 40;
  g.resolution = synthetic::Resolution{376, 240};
  g.out = dir.path() / "data";
  synthetic::generate_dataset(g);

  const HostLoadStudy study = run_host_load_study(g.out, dir.path() / "load", 3);
  for (std::size_t i = 0; i < study.rounds.size(); ++i) {
    const HostLoadRound& r = study.rounds[i];
    std::printf(
        "[ figures ] round %zu, in suite units, quiet: frontend %.2f, backend %.2f, kernels %.2f "
        "(suite %.1f / %.2f ms, %.2f s wall); busy siblings: frontend %.2f, backend %.2f, "
        "kernels %.2f (suite %.1f / %.2f ms, %.2f s wall)\n",
        i, r.quiet.frontend, r.quiet.backend, r.quiet.kernels, r.quiet.suite_frontend_ms,
        r.quiet.suite_backend_ms, r.quiet.wall_s, r.busy.frontend, r.busy.backend, r.busy.kernels,
        r.busy.suite_frontend_ms, r.busy.suite_backend_ms, r.busy.wall_s);
    // The modeled host times read only the work, which the load does not change: identical.
    const arch::PlatformHostTimes quiet = modeled_times(r.quiet_trace);
    const arch::PlatformHostTimes busy = modeled_times(r.busy_trace);
    EXPECT_EQ(busy.frontend_ms, quiet.frontend_ms) << "round " << i;
    EXPECT_EQ(busy.backend_ms, quiet.backend_ms) << "round " << i;
    EXPECT_EQ(busy.kernel_ms, quiet.kernel_ms) << "round " << i;
  }
  std::printf(
      "[ figures ] busy / quiet, median of %zu rounds: frontend %.3f, backend %.3f, kernels %.3f "
      "in suite units; wall clock %.3f\n",
      study.rounds.size(), study.frontend_ratio, study.backend_ratio, study.kernels_ratio,
      study.wall_ratio);
  // The siblings take the traced thread's core part of the time: a wall clock records much more.
  EXPECT_GT(study.wall_ratio, 1.3);
  // Measured host times (host.times: measured) in suite units move at most half as far as the
  // wall clock does. How far they move is the machine's (issue 17's 10 % bar holds on the
  // development VM, not on every CI machine: docs/MODEL.md, "Host times"); `edx bench host-load`
  // reports it.
  const double wall_shift = study.wall_ratio - 1.0;
  EXPECT_LT(std::abs(study.frontend_ratio - 1.0), 0.5 * wall_shift);
  EXPECT_LT(std::abs(study.backend_ratio - 1.0), 0.5 * wall_shift);
  EXPECT_LT(std::abs(study.kernels_ratio - 1.0), 0.5 * wall_shift);
}

}  // namespace
}  // namespace edx::modes
