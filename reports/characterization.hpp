#pragma once
// The paper's algorithm characterization (Sec. III; issue 42) as a study: the runs of
// workloads/modes/characterization.hpp (each backend on each scenario, several seeds) with their
// frame rate on a platform's CPU-only baseline (the modeled host of its `host:`/`baseline_host:`,
// Edx-Car's Kaby Lake by default), aggregated per (scenario, backend) over the seeds, and the
// paper's statements beside them (reports/paper_targets.yaml `characterization:`):
//
//   fps(run)   = 1000 / mean over the measured segment's frames of the baseline's e2e ms
//   ATE        = mean and SD over the seeds of each run's ATE RMSE (m)
//
// per scenario: which backend errs least and which is fastest, edx's and the paper's.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arch/platform/platform.hpp"
#include "common/config_fields.hpp"
#include "workloads/modes/characterization.hpp"

namespace edx::reports {

/// The paper's figure for one (scenario, backend), as far as its text states it.
struct PaperCharacterizationPoint {
  std::string scenario, backend;
  std::optional<double> ate_m, fps;
};

/// The paper's statements (reports/paper_targets.yaml `characterization:`): its points and, per
/// scenario, the backend with the least error and (when it says) the fastest.
struct PaperCharacterization {
  std::vector<PaperCharacterizationPoint> points;
  struct Scenario {
    std::string scenario, least_error, fastest;  ///< "" when the paper does not say
  };
  std::vector<Scenario> scenarios;
  std::string source;
  /// Reads the `characterization:` section of `targets_file`; errors name the file, line and key.
  static PaperCharacterization load(const std::filesystem::path& targets_file);
};

/// The keys of the targets file's `characterization:` section (docs/CONFIG.md, "Other input
/// files").
std::vector<ReferenceRow> paper_characterization_reference();

/// One (scenario, backend) over the seeds.
struct CharacterizationPoint {
  std::string scenario, backend;
  std::size_t seeds = 0;
  std::size_t seeds_without_ate = 0;  ///< runs with too few estimates for an ATE
  double ate_mean_m = 0, ate_sd_m = 0, ate_max_m = 0;
  double fps_mean = 0, fps_sd = 0;
  double e2e_mean_ms = 0;
  std::optional<double> paper_ate_m, paper_fps;
};

struct CharacterizationStudy {
  std::string platform;  ///< the platform whose baseline host the frame rates are on
  int frames = 0;
  std::string resolution;
  std::vector<std::uint64_t> seeds;
  std::vector<modes::CharacterizationRun> runs;
  std::vector<double> run_fps;  ///< per run
  std::vector<CharacterizationPoint> points;
  /// Per scenario (the paper's order): edx's least-error and fastest backend, the paper's.
  struct ScenarioResult {
    std::string scenario;
    std::string least_error, fastest;
    std::string paper_least_error, paper_fastest;
  };
  std::vector<ScenarioResult> scenarios;
  nlohmann::json to_json() const;
};

/// The study of `runs` with their frame rates on `platform`'s baseline (each trace simulated
/// with the analytical system model) and the paper's statements.
CharacterizationStudy study_characterization(const std::vector<modes::CharacterizationRun>& runs,
                                             const arch::Platform& platform,
                                             const PaperCharacterization& paper);

/// The metric tree `edx check --characterization FILE` adds under "characterization" from a
/// study's JSON (CharacterizationStudy::to_json, FILE as `edx characterize` wrote it):
///   <scenario>.<backend>.ate_m, .fps            the point's mean ATE and FPS
///   <scenario>.least_error_matches, .fastest_matches
///                                               1 when edx's backend is the paper's, else 0
///                                               (only where the paper states one)
/// Throws std::runtime_error naming `where` when the JSON is not such a study.
nlohmann::json characterization_metrics(const nlohmann::json& study, const std::string& where);

/// Text tables: per point, edx's ATE and FPS beside the paper's; per scenario, the orderings.
std::string format_characterization(const CharacterizationStudy& study);

}  // namespace edx::reports
