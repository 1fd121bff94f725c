#pragma once
// How a trace's measured host times move with the machine's load (issue 17; docs/MODEL.md,
// "Host times"): the same dataset traced on a quiet machine and beside sibling processes that
// keep every core busy, in rounds of one quiet and one busy trace each. Host times are compared
// in units of each trace's own reference-suite times (trace/host_speed.hpp), the units arch maps
// them by; the wall-clock time of the same runs shows what a wall clock would have recorded.
// Used by the load test (tests/workloads/modes/host_time_load_test.cpp) and `edx bench
// host-load`, which reports the rounds against issue 17's 10 % bar.
#include <sys/types.h>

#include <filesystem>
#include <vector>

namespace edx::modes {

/// Children that spin until destroyed, one per core: every core is kept busy and a traced
/// thread shares one with a spinner.
class BusySiblings {
 public:
  BusySiblings();
  ~BusySiblings();
  BusySiblings(const BusySiblings&) = delete;
  BusySiblings& operator=(const BusySiblings&) = delete;
  std::size_t count() const { return children_.size(); }

 private:
  std::vector<pid_t> children_;
};

/// One trace's host-time totals: the frontend over its suite's frontend part, the backend and
/// its kernels over the backend part (t / S_trace, the ratio a platform's measured host time
/// follows, arch/host/host_model.hpp), the suite medians, and the run's wall-clock seconds.
struct HostTimeTotals {
  double frontend = 0, backend = 0, kernels = 0;  ///< in suite units
  double suite_frontend_ms = 0, suite_backend_ms = 0;
  double wall_s = 0;
};

/// Traces `dataset` (SLAM backend, the trace runner's defaults) into `out` and returns its
/// totals.
HostTimeTotals trace_host_time_totals(const std::filesystem::path& dataset,
                                      const std::filesystem::path& out);

struct HostLoadRound {
  HostTimeTotals quiet, busy;
  std::filesystem::path quiet_trace, busy_trace;
  double frontend_ratio() const { return busy.frontend / quiet.frontend; }
  double backend_ratio() const { return busy.backend / quiet.backend; }
  double kernels_ratio() const { return busy.kernels / quiet.kernels; }
  double wall_ratio() const { return busy.wall_s / quiet.wall_s; }
};

struct HostLoadStudy {
  std::vector<HostLoadRound> rounds;
  /// Medians over the rounds of busy / quiet.
  double frontend_ratio = 0, backend_ratio = 0, kernels_ratio = 0, wall_ratio = 0;
};

/// A warm-up trace (one-time costs: page faults of fresh allocations, lazy initialization),
/// then `rounds` rounds, each a quiet trace and a busy one right after it: the machine's own
/// speed may drift over tens of seconds, so each busy trace is compared with the quiet one just
/// before it. Traces go to `work_dir` (created). Throws std::invalid_argument for rounds < 1.
HostLoadStudy run_host_load_study(const std::filesystem::path& dataset,
                                  const std::filesystem::path& work_dir, int rounds);

}  // namespace edx::modes
