#pragma once
// `edx check`: the paper's Edx-Car figures (reports/paper_targets.yaml) against a simulated run
// (docs/REPORTS.md, "Paper check"). A target passes when |simulated − paper| <= tolerance ·
// |paper|; a metric the run does not hold counts as a miss ("not found"), unless the run cannot
// hold it: its backend mode has no frames in the run ("n/a", not counted). Over several runs of
// one workload (seeds) each figure is their mean with its 95 % Student-t interval
// (reports/confidence.hpp), judged against the tolerance band.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/config_fields.hpp"
#include "reports/confidence.hpp"

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
/// characterization: `edx check --characterization`); kNotApplicable: the target's metric belongs
/// to a backend mode (metric_mode) that the run has no frames of (modes_with_frames), so the run
/// cannot have it. Both are shown, not counted (neither a pass nor a miss).
enum class Verdict { kPass, kMiss, kNotFound, kNotRun, kNotApplicable };
/// "pass", "MISS", "MISS (not found)", "not run", "n/a".
const char* to_string(Verdict v);
/// The verdict's key in `edx check --json`: "pass", "miss", "not_found", "not_run", "n/a".
const char* json_key(Verdict v);

/// The metric trees' optional studies: top-level keys a run's metrics hold only when the study
/// was given ("characterization").
bool is_optional_study_metric(const std::string& metric);

struct CheckRow {
  PaperTarget target;
  std::optional<double> simulated;       ///< over several runs: their mean
  double error = 0;                      ///< (simulated − paper) / |paper|
  Verdict verdict = Verdict::kNotFound;  ///< of `simulated` (over runs: of the mean)
  std::string absent_mode;               ///< kNotApplicable: the mode the run has no frames of
  /// Over several runs (check_targets_over_runs): the 95 % interval of the mean and where it
  /// lies against the tolerance band; absent for one run's check.
  std::optional<Interval> interval;
  std::optional<IntervalVerdict> interval_verdict;
};

struct CheckResult {
  std::string run_id;  ///< over several runs: their ids joined by ", "
  std::size_t runs = 1;
  std::vector<CheckRow> rows;
  std::size_t passed() const;
  std::size_t counted() const;  ///< rows neither kNotRun nor kNotApplicable
  std::size_t count(Verdict v) const;
  bool all_passed() const { return passed() == counted(); }
  nlohmann::json to_json() const;
};

/// Compares each target with the metric tree of one run (run_metrics, plus "frontend"). A target
/// of a mode the tree's run has no frames of is kNotApplicable, whatever the tree holds there.
CheckResult check_targets(const std::vector<PaperTarget>& targets, const nlohmann::json& metrics,
                          const std::string& run_id);

/// Compares each target with several runs of the same workload (seeds), `runs` their metric
/// trees and `run_ids` their ids (same length, at least one). A target every run holds: the mean
/// (its pass / MISS verdict as check_targets judges a value), its 95 % Student-t interval and
/// the interval's verdict against [paper − tol·|paper|, paper + tol·|paper|]. A target some run
/// does not hold: that run's verdict (n/a, not run or not found) and no interval. Throws
/// std::invalid_argument for no runs or unequal lengths.
CheckResult check_targets_over_runs(const std::vector<PaperTarget>& targets,
                                    const std::vector<nlohmann::json>& runs,
                                    const std::vector<std::string>& run_ids);

/// Whether a run is of Edx-Car, the platform whose figures paper_targets.yaml and Table III
/// hold: its platform is named edx_car (configs/edx_car.yaml) and its design is on Table III's
/// device (XC7V690T; the run summary's resources.device). The report shows the paper check and
/// the Table III comparison only for such runs.
bool is_edx_car_run(const RunData& run);

/// The table `edx check` prints: name, paper, simulated, error, tolerance, verdict per row, then
/// the count, the n/a rows and the metrics not found. Over several runs the simulated column is
/// "mean [low, high]" and a column gives the interval verdict.
std::string format_check(const CheckResult& result);

}  // namespace edx::reports
