#pragma once
// The paper check of a platform simulated here (`edx check --config --trace`, and over seeds
// `--workload --seeds`): the run and the compared baselines' platforms on the same trace, passed
// through a scratch results database (one reading path with `edx check --results`), plus the
// frontend study, which the results database does not hold (docs/REPORTS.md, "Paper check").
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/platform/platform.hpp"
#include "reports/paper_check.hpp"

namespace edx::reports {

struct SimulatedRun {
  std::string run_id;
  nlohmann::json metrics;  ///< the metric tree (reports/metrics.hpp), frontend.* included
};

/// `platform` and each of `baselines` (but the platform's own) simulated on `trace`.
SimulatedRun simulate_for_check(const arch::Platform& platform, const std::filesystem::path& trace,
                                const std::vector<ComparedBaseline>& baselines);

}  // namespace edx::reports
