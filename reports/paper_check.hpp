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

enum class Verdict { kPass, kMiss, kNotFound };

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
  bool all_passed() const { return passed() == rows.size(); }
  nlohmann::json to_json() const;
};

/// Compares each target with the metric tree of one run (run_metrics, plus "frontend").
CheckResult check_targets(const std::vector<PaperTarget>& targets, const nlohmann::json& metrics,
                          const std::string& run_id);

/// The table `edx check` prints: name, paper, simulated, error, tolerance, verdict per row, then
/// the count and the metrics not found.
std::string format_check(const CheckResult& result);

}  // namespace edx::reports
