#pragma once
// `edx check`: the paper's Edx-Car figures (reports/paper_targets.yaml) against a simulated run
// (docs/REPORTS.md, "Paper check"). A target passes when |simulated − paper| <= tolerance ·
// |paper|; a metric the run does not hold counts as a miss ("not found").
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/config_fields.hpp"

namespace edx::reports {

struct PaperTarget {
  std::string name;
  std::string metric;  ///< dotted path in the run's metric tree (reports/metrics.hpp)
  double paper = 0;
  double tolerance = 0.10;  ///< relative
  std::string unit, source;
  /// Anchor of docs/MODEL.md (`<a id="...">`) explaining why the model misses this target, when
  /// it does; empty: none (the report links the section of all misses).
  std::string explained;
  int line = 0;  ///< 1-based line of the target in its file
};

/// A platform the paper compares Edx-Car with (its Table "Edx-Car speedup over CPU/GPU/DSP"):
/// a platform file whose CPU-only baseline variant is that baseline, simulated on the same trace.
struct ComparedBaseline {
  std::string name;         ///< metric key: baselines.<name>.speedup
  std::string config;       ///< the platform file, relative to edx's data folder
  std::string description;  ///< the paper's row
  int line = 0;
};

/// The `baselines:` list of a targets file (empty when it has none). Errors as load_targets.
std::vector<ComparedBaseline> load_baselines(const std::filesystem::path& path);

/// The platform name of a baseline's config file (its `name:`), its path resolved in edx's data
/// folder. Throws std::runtime_error naming the file when it is missing or has no name.
std::string baseline_platform(const ComparedBaseline& baseline);

struct RunData;
struct ResultsData;
/// Adds `baselines.<name>.{e2e_ms, speedup, slowdown}` to `metrics` (the metric tree of `run`)
/// for each baseline that `data` holds a run of on the same trace (its platform, the run's
/// trace hash): e2e_ms its baseline variant's mean end-to-end latency, speedup that over `run`'s
/// accelerated mean, slowdown that over `run`'s own baseline mean, minus 1. A baseline without
/// such a run is left out (its targets: not found).
void add_baseline_metrics(nlohmann::json& metrics, const ResultsData& data, const RunData& run,
                          const std::vector<ComparedBaseline>& baselines);

/// Reads and validates a targets file: a map with `targets` (a sequence of maps with name,
/// metric, paper and optional unit, tolerance, source, explained) and an optional default
/// `tolerance`, each map read from its field list (paper_check.cpp). Errors: InputError
/// "file:line: key: what was expected".
std::vector<PaperTarget> load_targets(const std::filesystem::path& path);

/// The keys of a targets file (its top level, a target), for the reference (docs/CONFIG.md,
/// "Other input files").
std::vector<ReferenceRow> paper_targets_reference();

/// The default targets file: reports/paper_targets.yaml of edx's data folder (installed, else
/// the source tree; common/resources.hpp). Throws std::runtime_error when it is missing.
std::filesystem::path default_targets_path();

/// kNotRun: the target's metric belongs to an optional study that was not given (the
/// characterization: `edx check --characterization`); such a row is shown, not counted.
enum class Verdict { kPass, kMiss, kNotFound, kNotRun };
/// "pass", "MISS", "MISS (not found)", "not run".
const char* to_string(Verdict v);

/// The metric trees' optional studies: top-level keys a run's metrics hold only when the study
/// was given ("characterization").
bool is_optional_study_metric(const std::string& metric);

struct CheckRow {
  PaperTarget target;
  std::optional<double> simulated;
  double error = 0;  ///< (simulated − paper) / |paper|
  Verdict verdict = Verdict::kNotFound;
};

struct CheckResult {
  std::string run_id;
  std::vector<CheckRow> rows;
  std::size_t passed() const;
  std::size_t counted() const;  ///< rows not kNotRun
  bool all_passed() const { return passed() == counted(); }
  nlohmann::json to_json() const;
};

/// Compares each target with the metric tree of one run (run_metrics, plus "frontend").
CheckResult check_targets(const std::vector<PaperTarget>& targets, const nlohmann::json& metrics,
                          const std::string& run_id);

/// The table `edx check` prints: name, paper, simulated, error, tolerance, verdict per row, then
/// the count and the metrics not found.
std::string format_check(const CheckResult& result);

}  // namespace edx::reports
