#include "reports/paper_check.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "common/resources.hpp"
#include "reports/metrics.hpp"

namespace edx::reports {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const YAML::Node& node,
                       const std::string& key, const std::string& expected) {
  throw std::runtime_error(
      fmt::format("{}:{}: {}: {}", path.string(), node.Mark().line + 1, key, expected));
}

double number(const std::filesystem::path& path, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) fail(path, node, key, "expected a number");
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) fail(path, node, key, "expected a finite number");
    return v;
  } catch (const YAML::BadConversion&) {
    fail(path, node, key, fmt::format("expected a number, got '{}'", node.Scalar()));
  }
}

std::string string(const std::filesystem::path& path, const YAML::Node& node,
                   const std::string& key) {
  if (!node.IsScalar()) fail(path, node, key, "expected a string");
  return node.Scalar();
}

double tolerance(const std::filesystem::path& path, const YAML::Node& node,
                 const std::string& key) {
  const double t = number(path, node, key);
  if (t <= 0 || t >= 1) fail(path, node, key, "expected a relative tolerance in (0, 1)");
  return t;
}

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kMiss:
      return "MISS";
    case Verdict::kNotFound:
      break;
  }
  return "MISS (not found)";
}

}  // namespace

std::filesystem::path default_targets_path() {
  return common::find_resource("reports/paper_targets.yaml");
}

std::vector<PaperTarget> load_targets(const std::filesystem::path& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::BadFile&) {
    throw std::runtime_error(fmt::format("{}: cannot read the targets file", path.string()));
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}:{}: not valid YAML: {}", path.string(), e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) fail(path, root, "(top)", "expected a map with 'targets'");
  double default_tolerance = 0.10;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (key == "tolerance") {
      default_tolerance = tolerance(path, kv.second, key);
    } else if (key != "targets") {
      fail(path, kv.first, key, "unknown key (expected 'targets' or 'tolerance')");
    }
  }
  const YAML::Node list = root["targets"];
  if (!list) fail(path, root, "targets", "missing (expected a list of targets)");
  if (!list.IsSequence() || list.size() == 0) {
    fail(path, list, "targets", "expected a non-empty list of targets");
  }
  std::vector<PaperTarget> targets;
  std::set<std::string> names;
  for (const YAML::Node& item : list) {
    if (!item.IsMap()) fail(path, item, "targets[]", "expected a map (name, metric, paper, ...)");
    PaperTarget t;
    t.line = item.Mark().line + 1;
    t.tolerance = default_tolerance;
    bool has_name = false, has_metric = false, has_paper = false;
    for (const auto& kv : item) {
      const std::string key = kv.first.as<std::string>();
      if (key == "name") {
        t.name = string(path, kv.second, key);
        has_name = true;
      } else if (key == "metric") {
        t.metric = string(path, kv.second, key);
        has_metric = !t.metric.empty();
      } else if (key == "paper") {
        t.paper = number(path, kv.second, key);
        has_paper = true;
      } else if (key == "tolerance") {
        t.tolerance = tolerance(path, kv.second, key);
      } else if (key == "unit") {
        t.unit = string(path, kv.second, key);
      } else if (key == "source") {
        t.source = string(path, kv.second, key);
      } else if (key == "explained") {
        t.explained = string(path, kv.second, key);
        if (t.explained.empty() ||
            t.explained.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") !=
                std::string::npos) {
          fail(path, kv.second, key, "expected an anchor of docs/MODEL.md (a-z, 0-9, '-')");
        }
      } else {
        fail(path, kv.first, key,
             "unknown key (expected name, metric, paper, unit, tolerance, source, explained)");
      }
    }
    if (!has_name) fail(path, item, "name", "missing");
    if (!has_metric) fail(path, item, "metric", "missing (expected a dotted metric path)");
    if (!has_paper) fail(path, item, "paper", "missing (expected the paper's value)");
    if (t.paper == 0) fail(path, item, "paper", "expected a non-zero value (errors are relative)");
    if (!names.insert(t.name).second) {
      fail(path, item, "name", fmt::format("duplicate target '{}'", t.name));
    }
    targets.push_back(std::move(t));
  }
  return targets;
}

std::size_t CheckResult::passed() const {
  std::size_t n = 0;
  for (const CheckRow& r : rows) n += r.verdict == Verdict::kPass ? 1 : 0;
  return n;
}

nlohmann::json CheckResult::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const CheckRow& r : rows) {
    list.push_back({{"name", r.target.name},
                    {"metric", r.target.metric},
                    {"paper", r.target.paper},
                    {"simulated", r.simulated ? nlohmann::json(*r.simulated) : nullptr},
                    {"error", r.simulated ? nlohmann::json(r.error) : nullptr},
                    {"tolerance", r.target.tolerance},
                    {"unit", r.target.unit},
                    {"source", r.target.source},
                    {"explained", r.target.explained},
                    {"verdict", r.verdict == Verdict::kPass   ? "pass"
                                : r.verdict == Verdict::kMiss ? "miss"
                                                              : "not_found"}});
  }
  return {{"run_id", run_id},
          {"targets", rows.size()},
          {"passed", passed()},
          {"ok", all_passed()},
          {"rows", list}};
}

CheckResult check_targets(const std::vector<PaperTarget>& targets, const nlohmann::json& metrics,
                          const std::string& run_id) {
  CheckResult result;
  result.run_id = run_id;
  for (const PaperTarget& t : targets) {
    CheckRow row;
    row.target = t;
    row.simulated = metric_at(metrics, t.metric);
    if (row.simulated) {
      row.error = (*row.simulated - t.paper) / std::abs(t.paper);
      // A small epsilon keeps a value exactly on the tolerance edge a pass despite rounding.
      row.verdict = std::abs(row.error) <= t.tolerance + 1e-12 ? Verdict::kPass : Verdict::kMiss;
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

namespace {

/// A figure as a person reads it: integers for large counts, 4 significant digits otherwise.
std::string figure(double v) {
  return std::abs(v) >= 1000 ? fmt::format("{:.0f}", v) : fmt::format("{:.4g}", v);
}

}  // namespace

std::string format_check(const CheckResult& r) {
  std::string text =
      fmt::format("paper check of run {} (Edx-Car, reports/paper_targets.yaml)\n", r.run_id);
  text += fmt::format("{:<40} {:<8} {:>10} {:>10} {:>9} {:>5}  {}\n", "target", "unit", "paper",
                      "simulated", "error", "tol", "verdict");
  std::vector<std::string> not_found;
  for (const CheckRow& row : r.rows) {
    const std::string sim = row.simulated ? figure(*row.simulated) : "-";
    const std::string err = row.simulated ? fmt::format("{:+.1f}%", 100 * row.error) : "-";
    text += fmt::format("{:<40} {:<8} {:>10} {:>10} {:>9} {:>4.0f}%  {}\n", row.target.name,
                        row.target.unit, figure(row.target.paper), sim, err,
                        100 * row.target.tolerance, verdict_name(row.verdict));
    if (row.verdict == Verdict::kNotFound) not_found.push_back(row.target.metric);
  }
  text += fmt::format("{} of {} targets within tolerance", r.passed(), r.rows.size());
  if (!not_found.empty()) {
    text += fmt::format("; not found in the results: {}", fmt::join(not_found, ", "));
  }
  return text + "\n";
}

}  // namespace edx::reports
