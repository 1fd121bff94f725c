#include "reports/paper_check.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "arch/memory/bram.hpp"
#include "common/config_fields.hpp"
#include "common/resources.hpp"
#include "reports/metrics.hpp"
#include "reports/results_reader.hpp"

namespace edx::reports {
namespace {

/// The relative tolerance of a target, and the file's default for its targets.
Field<PaperTarget> tolerance_field() {
  return field("tolerance", &PaperTarget::tolerance, "",
               "relative: |simulated - paper| / |paper| <= tolerance passes",
               Bounds::above(0).below(1))
      .expects("a relative tolerance in (0, 1)");
}

/// The keys of a target (`targets:` items), in the order errors list them.
const FieldList<PaperTarget>& target_fields() {
  using C = PaperTarget;
  static const FieldList<C> list = {
      field("name", &C::name, "", "the target's name in the check's table").required("missing"),
      field("metric", &C::metric, "", "dotted path in the run's metric tree (reports/metrics.hpp)")
          .required("missing (expected a dotted metric path)"),
      field("paper", &C::paper, "", "the paper's value, in the metric's unit (not 0)")
          .required("missing (expected the paper's value)"),
      field("unit", &C::unit, "", "the metric's unit (display only)"),
      tolerance_field(),
      field("source", &C::source, "", "where in the paper"),
      field("explained", &C::explained, "",
            "the anchor of docs/MODEL.md that explains why the model misses it, when it does"),
  };
  return list;
}

/// The keys of a compared baseline (`baselines:` items).
const FieldList<ComparedBaseline>& baseline_fields() {
  using C = ComparedBaseline;
  static const FieldList<C> list = {
      field("name", &C::name, "", "the baseline's key in the metric tree (baselines.<name>)")
          .required("missing"),
      field("config", &C::config, "",
            "its platform file, relative to edx's data folder (configs/...)")
          .required("missing (expected a platform file)"),
      field("description", &C::description, "", "the paper's row"),
  };
  return list;
}

/// The rules of a target beyond its keys' values.
void check_target(const PaperTarget& t) {
  if (t.metric.empty()) throw InputError({}, "metric", "missing (expected a dotted metric path)");
  require_field(t.paper != 0, "", "paper", "a non-zero value (errors are relative)");
  require_field(t.explained.empty() ||
                    t.explained.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") ==
                        std::string::npos,
                "", "explained", "an anchor of docs/MODEL.md (a-z, 0-9, '-')");
}

}  // namespace

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kMiss:
      return "MISS";
    case Verdict::kNotRun:
      return "not run";
    case Verdict::kNotApplicable:
      return "n/a";
    case Verdict::kNotFound:
      break;
  }
  return "MISS (not found)";
}

const char* json_key(Verdict v) {
  switch (v) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kMiss:
      return "miss";
    case Verdict::kNotRun:
      return "not_run";
    case Verdict::kNotApplicable:
      return "n/a";
    case Verdict::kNotFound:
      break;
  }
  return "not_found";
}

bool is_optional_study_metric(const std::string& metric) {
  return metric.starts_with("characterization.");
}

std::filesystem::path default_targets_path() {
  return common::find_resource("reports/paper_targets.yaml");
}

std::vector<PaperTarget> load_targets(const std::filesystem::path& path) {
  const std::string where = path.string();
  const YAML::Node root =
      load_yaml_map(read_input_file(path, "targets file"), where, "'targets' and a 'tolerance'");
  YamlFields top(root, where, "");
  top.refuse_unknown({"targets", "tolerance", "baselines", "characterization"},
                     "expected 'targets', 'tolerance', 'baselines' or 'characterization'");
  PaperTarget defaults;  // every target's tolerance, unless it has its own
  parse_fields(top, defaults, {tolerance_field()});
  const YAML::Node list = top.take("targets");
  if (!list) top.fail("targets", "missing (expected a list of targets)");
  if (!list.IsSequence() || list.size() == 0) {
    top.fail("targets", "expected a non-empty list of targets");
  }
  std::vector<PaperTarget> targets;
  std::set<std::string> names;
  for (const YAML::Node& item : list) {
    if (!item.IsMap()) {
      throw InputError({where, yaml_line(item)}, "targets[]",
                       "expected a map (name, metric, paper, ...)");
    }
    PaperTarget t;
    t.tolerance = defaults.tolerance;
    t.line = yaml_line(item);
    YamlFields fields(item, where, "");
    fields.refuse_unknown(field_keys(target_fields()),
                          fmt::format("expected {}", fmt::join(field_keys(target_fields()), ", ")));
    parse_fields(fields, t, target_fields());
    validate_at(fields, [&t] { check_target(t); });
    if (!names.insert(t.name).second) {
      fields.fail("name", fmt::format("duplicate target '{}'", t.name));
    }
    targets.push_back(std::move(t));
  }
  return targets;
}

std::vector<ComparedBaseline> load_baselines(const std::filesystem::path& path) {
  const std::string where = path.string();
  const YAML::Node root =
      load_yaml_map(read_input_file(path, "targets file"), where, "'targets' and a 'tolerance'");
  YamlFields top(root, where, "");
  const YAML::Node list = top.take("baselines");
  std::vector<ComparedBaseline> baselines;
  if (!list) return baselines;
  if (!list.IsSequence()) top.fail("baselines", "expected a list of baselines");
  std::set<std::string> names;
  for (const YAML::Node& item : list) {
    if (!item.IsMap()) {
      throw InputError({where, yaml_line(item)}, "baselines[]",
                       "expected a map (name, config, description)");
    }
    ComparedBaseline b;
    b.line = yaml_line(item);
    YamlFields fields(item, where, "baselines[]");
    fields.refuse_unknown(field_keys(baseline_fields()), "expected name, config, description");
    parse_fields(fields, b, baseline_fields());
    if (b.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos) {
      fields.fail("name", "expected a metric key (a-z, 0-9, '_')");
    }
    if (!names.insert(b.name).second) {
      fields.fail("name", fmt::format("duplicate baseline '{}'", b.name));
    }
    baselines.push_back(std::move(b));
  }
  return baselines;
}

std::string baseline_platform(const ComparedBaseline& baseline) {
  const std::filesystem::path file = common::find_resource(baseline.config);
  const YAML::Node root =
      load_yaml_map(read_input_file(file, "platform file"), file.string(), "a platform");
  const YAML::Node name = root["name"];
  if (!name || !name.IsScalar() || name.Scalar().empty()) {
    throw std::runtime_error(fmt::format(
        "{}: name: missing (a compared baseline's platform needs its own name)", file.string()));
  }
  return name.Scalar();
}

void add_baseline_metrics(nlohmann::json& metrics, const ResultsData& data, const RunData& run,
                          const std::vector<ComparedBaseline>& baselines) {
  const nlohmann::json::json_pointer e2e("/system/baseline/modes/all/e2e_ms/mean");
  const nlohmann::json::json_pointer accelerated("/system/accelerated/modes/all/e2e_ms/mean");
  if (!metrics.contains(accelerated) || !metrics.contains(e2e)) return;
  const double accelerated_ms = metrics.at(accelerated).get<double>();
  const double own_baseline_ms = metrics.at(e2e).get<double>();
  for (const ComparedBaseline& b : baselines) {
    const std::string platform = baseline_platform(b);
    for (const RunData& other : data.runs) {
      if (other.platform != platform || other.trace_hash != run.trace_hash) continue;
      const nlohmann::json m = &other == &run ? metrics : run_metrics(other);
      if (!m.contains(e2e)) break;
      const double baseline_ms = m.at(e2e).get<double>();
      metrics["baselines"][b.name] = {{"e2e_ms", baseline_ms},
                                      {"speedup", baseline_ms / accelerated_ms},
                                      {"slowdown", baseline_ms / own_baseline_ms - 1},
                                      {"platform", platform}};
      break;
    }
  }
}

std::vector<ReferenceRow> paper_targets_reference() {
  const std::string file = "Paper targets (`reports/paper_targets.yaml`)";
  std::vector<ReferenceRow> rows =
      reference_rows("", FieldList<PaperTarget>{tolerance_field()}, {}, file + ": top level");
  for (ReferenceRow& row :
       reference_rows("targets[]", target_fields(), {}, file + ": `targets: [{...}]`")) {
    rows.push_back(std::move(row));
  }
  for (ReferenceRow& row : reference_rows("baselines[]", baseline_fields(), {},
                                          file + ": `baselines: [{...}]` (compared platforms)")) {
    rows.push_back(std::move(row));
  }
  return rows;
}

std::size_t CheckResult::count(Verdict v) const {
  std::size_t n = 0;
  for (const CheckRow& r : rows) n += r.verdict == v ? 1 : 0;
  return n;
}

std::size_t CheckResult::passed() const { return count(Verdict::kPass); }

std::size_t CheckResult::counted() const {
  return rows.size() - count(Verdict::kNotRun) - count(Verdict::kNotApplicable);
}

nlohmann::json CheckResult::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const CheckRow& r : rows) {
    nlohmann::json row = {{"name", r.target.name},
                          {"metric", r.target.metric},
                          {"paper", r.target.paper},
                          {"simulated", r.simulated ? nlohmann::json(*r.simulated) : nullptr},
                          {"error", r.simulated ? nlohmann::json(r.error) : nullptr},
                          {"tolerance", r.target.tolerance},
                          {"unit", r.target.unit},
                          {"source", r.target.source},
                          {"explained", r.target.explained},
                          {"verdict", json_key(r.verdict)}};
    if (r.verdict == Verdict::kNotApplicable) row["absent_mode"] = r.absent_mode;
    if (r.interval) {
      row["interval"] = {{"mean", r.interval->mean},
                         {"low", r.interval->low},
                         {"high", r.interval->high},
                         {"n", r.interval->n},
                         {"has_spread", r.interval->has_spread()}};
    }
    if (r.interval_verdict) row["interval_verdict"] = to_string(*r.interval_verdict);
    list.push_back(std::move(row));
  }
  return {{"run_id", run_id},
          {"runs", runs},
          {"targets", counted()},
          {"not_run", count(Verdict::kNotRun)},
          {"not_applicable", count(Verdict::kNotApplicable)},
          {"passed", passed()},
          {"ok", all_passed()},
          {"rows", list}};
}

namespace {

/// A row's value, error and pass / MISS verdict.
void judge(CheckRow& row, double value) {
  row.simulated = value;
  row.error = (value - row.target.paper) / std::abs(row.target.paper);
  row.verdict = within_tolerance(row.error, row.target.tolerance) ? Verdict::kPass : Verdict::kMiss;
}

}  // namespace

CheckResult check_targets(const std::vector<PaperTarget>& targets, const nlohmann::json& metrics,
                          const std::string& run_id) {
  CheckResult result;
  result.run_id = run_id;
  const std::optional<std::set<std::string>> modes = modes_with_frames(metrics);
  for (const PaperTarget& t : targets) {
    CheckRow row;
    row.target = t;
    const std::optional<std::string> mode = metric_mode(t.metric);
    if (mode && modes && !modes->contains(*mode)) {
      row.verdict = Verdict::kNotApplicable;
      row.absent_mode = *mode;
    } else if (const std::optional<double> value = metric_at(metrics, t.metric)) {
      judge(row, *value);
    } else if (is_optional_study_metric(t.metric) &&
               !metrics.contains(t.metric.substr(0, t.metric.find('.')))) {
      row.verdict = Verdict::kNotRun;
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

CheckResult check_targets_over_runs(const std::vector<PaperTarget>& targets,
                                    const std::vector<nlohmann::json>& runs,
                                    const std::vector<std::string>& run_ids) {
  if (runs.empty() || runs.size() != run_ids.size()) {
    throw std::invalid_argument(fmt::format(
        "check over runs: {} metric trees and {} run ids (expected the same number, at least 1)",
        runs.size(), run_ids.size()));
  }
  std::vector<CheckResult> each;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    each.push_back(check_targets(targets, runs[i], run_ids[i]));
  }
  CheckResult result;
  result.run_id = fmt::format("{}", fmt::join(run_ids, ", "));
  result.runs = runs.size();
  for (std::size_t t = 0; t < targets.size(); ++t) {
    CheckRow row;
    row.target = targets[t];
    std::vector<double> values;
    for (const CheckResult& run : each) {
      const CheckRow& r = run.rows[t];
      if (!r.simulated) {  // a run without the figure: its verdict is the row's
        row.verdict = r.verdict;
        row.absent_mode = r.absent_mode;
        break;
      }
      values.push_back(*r.simulated);
    }
    if (values.size() == runs.size()) {
      const Interval interval = student_t_interval(values, row.target.name);
      judge(row, interval.mean);
      row.interval = interval;
      row.interval_verdict = interval_verdict(interval, row.target.paper, row.target.tolerance);
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

bool is_edx_car_run(const RunData& run) {
  const nlohmann::json::json_pointer device("/resources/device");
  if (run.platform != "edx_car" || !run.summary.contains(device) ||
      !run.summary.at(device).is_string()) {
    return false;
  }
  const std::optional<arch::Device> d =
      arch::Device::find(run.summary.at(device).get<std::string>());
  return d && d->name == arch::Device::xc7v690t().name;
}

namespace {

/// A figure as a person reads it: integers for large counts, 4 significant digits otherwise.
std::string figure(double v) {
  return std::abs(v) >= 1000 ? fmt::format("{:.0f}", v) : fmt::format("{:.4g}", v);
}

}  // namespace

std::string format_check(const CheckResult& r) {
  bool intervals = false;
  std::vector<std::string> simulated;  // per row: the value, or "mean [low, high]"
  std::size_t width = 10;
  for (const CheckRow& row : r.rows) {
    std::string sim = row.simulated ? figure(*row.simulated) : "-";
    if (row.interval) {
      intervals = true;
      sim = fmt::format("{} [{}, {}]", sim, figure(row.interval->low), figure(row.interval->high));
    }
    width = std::max(width, sim.size());
    simulated.push_back(std::move(sim));
  }
  std::string text =
      r.runs > 1
          ? fmt::format(
                "paper check over {} runs ({}; mean [95% Student-t interval]) "
                "(Edx-Car, reports/paper_targets.yaml)\n",
                r.runs, r.run_id)
          : fmt::format("paper check of run {} (Edx-Car, reports/paper_targets.yaml)\n", r.run_id);
  text +=
      fmt::format("{:<40} {:<8} {:>10} {:>{}} {:>9} {:>5}  {:<16}{}\n", "target", "unit", "paper",
                  "simulated", width, "error", "tol", "verdict", intervals ? " interval" : "");
  std::vector<std::string> not_found;
  std::set<std::string> absent_modes;
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const CheckRow& row = r.rows[i];
    const std::string err = row.simulated ? fmt::format("{:+.1f}%", 100 * row.error) : "-";
    const std::string interval =
        !intervals ? "" : (row.interval_verdict ? to_string(*row.interval_verdict) : "-");
    std::string line =
        fmt::format("{:<40} {:<8} {:>10} {:>{}} {:>9} {:>4.0f}%  {:<16} {}", row.target.name,
                    row.target.unit, figure(row.target.paper), simulated[i], width, err,
                    100 * row.target.tolerance, to_string(row.verdict), interval);
    line.erase(line.find_last_not_of(' ') + 1);
    text += line + "\n";
    if (row.verdict == Verdict::kNotFound) not_found.push_back(row.target.metric);
    if (row.verdict == Verdict::kNotApplicable) absent_modes.insert(row.absent_mode);
  }
  text += fmt::format("{} of {} targets within tolerance", r.passed(), r.counted());
  if (const std::size_t n = r.count(Verdict::kNotApplicable); n > 0) {
    text += fmt::format("; {} n/a (the run has no frames of their mode: {})", n,
                        fmt::join(absent_modes, ", "));
  }
  if (const std::size_t n = r.count(Verdict::kNotRun); n > 0) {
    text += fmt::format(
        "; {} not run (the characterization's: edx characterize, then --characterization)", n);
  }
  if (!not_found.empty()) {
    text += fmt::format("; not found in the results: {}", fmt::join(not_found, ", "));
  }
  return text + "\n";
}

}  // namespace edx::reports
