// Reading a sweep spec (sweep.hpp, docs/SWEEPS.md): each map of the spec is read from its field
// list (common/config_fields.hpp), the lists and the rules between keys by a reader of their
// own, one per section; every error is an InputError at the spec's file, line and key.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <optional>

#include "arch/sweep/sweep.hpp"
#include "common/config_fields.hpp"

namespace edx::arch {
namespace {

[[noreturn]] void fail(const std::string& where, const YAML::Node& node, const std::string& key,
                       const std::string& message) {
  throw InputError({where, node ? yaml_line(node) : 0}, key, message);
}

/// The hint of an unknown key: "expected one of: a, b, c".
std::string one_of(const std::vector<std::string>& keys) {
  return fmt::format("expected one of: {}", fmt::join(keys, ", "));
}

/// Reads the map `node` (key `key`) into `config` from `list`, any other key refused first
/// (naming the keys it may hold); `shape` is the error when `node` is no map.
template <class Config>
void read_map(const std::string& where, const std::string& key, const YAML::Node& node,
              const std::string& shape, const FieldList<Config>& list, Config& config) {
  if (!node.IsMap()) fail(where, node, key, "expected " + shape);
  YamlFields fields(node, where, key);
  fields.refuse_unknown(field_keys(list), one_of(field_keys(list)));
  parse_fields(fields, config, list);
}

/// The keys of a spec's top level that are plain values; workload, parameters, sampling,
/// objectives and constraints have readers of their own.
struct SpecHeader {
  std::string name, description, base, trace;
  static const FieldList<SpecHeader>& fields() {
    using C = SpecHeader;
    static const FieldList<C> list = {
        field("name", &C::name, "",
              "the sweep's id in the results database (default: the file's stem)"),
        field("description", &C::description, "", "one line for people"),
        field("base", &C::base, "", "the base platform file, relative to the spec").required(),
        field("trace", &C::trace, "",
              "the trace simulated, relative to the spec (`--trace` overrides it); not with "
              "workload:"),
    };
    return list;
  }
};

const std::vector<std::string> kSectionKeys = {"workload", "parameters", "sampling", "objectives",
                                               "constraints"};

/// `parameters.<key>: {range: {from, to, step}}`: from, from + step, ... up to to.
struct LinearRange {
  double from = 0, to = 0, step = 0;
  static const FieldList<LinearRange>& fields() {
    using C = LinearRange;
    static const FieldList<C> list = {
        field("from", &C::from, "", "the first value").required(),
        field("to", &C::to, "", "the last value at most (>= from)").required(),
        field("step", &C::step, "", "between values (> 0)").required(),
    };
    return list;
  }
};

/// `parameters.<key>: {log_range: {from, to, points}}`: `points` values from `from` to `to`,
/// geometrically spaced.
struct LogRange {
  double from = 0, to = 0, points = 0;
  static const FieldList<LogRange>& fields() {
    using C = LogRange;
    static const FieldList<C> list = {
        field("from", &C::from, "", "the first value (> 0)").required(),
        field("to", &C::to, "", "the last value (> 0)").required(),
        field("points", &C::points, "", "values, both ends included (an integer >= 2)").required(),
    };
    return list;
  }
};

/// `sampling: {random: {samples, seed}}`.
const FieldList<SweepSpec>& random_sampling_fields() {
  using C = SweepSpec;
  static const FieldList<C> list = {
      field("samples", &C::samples, "", "distinct grid points drawn",
            Bounds::at_least(1).at_most(kMaxSweepPoints))
          .expects("an integer from 1 to 10^6")
          .required(),
      // 2^53: the largest range in which every integer is a double, far inside std::uint64_t.
      field("seed", &C::seed, "", "of the draws (splitmix64): the same seed, the same points",
            Bounds::at_least(0).at_most(kMaxSearchGrid))
          .expects("an integer from 0 to 2^53"),
  };
  return list;
}

/// `sampling: {nsga2: {generations, population, seed}}`.
const FieldList<SweepSpec>& nsga2_sampling_fields() {
  using C = SweepSpec;
  static const FieldList<C> list = {
      field("generations", &C::generations, "", "generations evolved after the initial one",
            Bounds::at_least(1).at_most(10000))
          .expects("an integer from 1 to 10000")
          .required(),
      // pagmo's NSGA-II pairs parents four at a time: at least 8, a multiple of 4.
      field("population", &C::population, "", "designs per generation",
            Bounds::at_least(8).at_most(10000).multiple_of(4))
          .expects("a multiple of 4 from 8 to 10000")
          .required(),
      // pagmo seeds are unsigned 32-bit integers.
      field("seed", &C::seed, "", "of pagmo's NSGA-II", Bounds::at_least(0).at_most(4294967295.0))
          .expects("an integer from 0 to 2^32 - 1"),
  };
  return list;
}

/// `constraints: [{metric, min, max}]` or `[{metric, max_relative, reference}]`, one item.
struct ConstraintEntry {
  std::string metric;
  std::optional<double> min, max, max_relative;
  static const FieldList<ConstraintEntry>& fields() {
    using C = ConstraintEntry;
    static const FieldList<C> list = {
        field("metric", &C::metric, "", "a metric of the run (docs/SWEEPS.md)").required(),
        optional_field("min", &C::min, "", "the least value a feasible point has", {},
                       Unset{"none", nullptr}),
        optional_field("max", &C::max, "", "the largest value a feasible point has", {},
                       Unset{"none", nullptr}),
        optional_field("max_relative", &C::max_relative, "",
                       "an accuracy metric at most (1 + max_relative) x its value at the "
                       "point's reference (with reference:)",
                       Bounds::at_least(0), Unset{"none", nullptr}),
    };
    return list;
  }
};

/// from + i·step for i = 0 .. floor((to − from)/step) (a relative 1e-9 slack keeps `to`).
void read_linear_range(const std::string& where, const std::string& key, const YAML::Node& node,
                       SweepParameter& p) {
  LinearRange r;
  read_map(where, key, node, "{from, to, step}", LinearRange::fields(), r);
  if (!(r.step > 0) || r.to < r.from) fail(where, node, key, "expected step > 0 and to >= from");
  // The count as a double first: (to - from) / step may overflow any integer (or be inf).
  const double last = std::floor((r.to - r.from) / r.step * (1 + 1e-12) + 1e-9);
  if (!(last < 100000)) {
    fail(where, node, key,
         std::isfinite(last) ? fmt::format("{:.4g} values (at most 100000)", last + 1)
                             : std::string("more than 100000 values"));
  }
  p.form = SweepParameter::Form::kLinear;
  p.from = r.from;
  p.to = r.to;
  p.step = r.step;
  p.count = static_cast<std::size_t>(last) + 1;
}

/// Geometric: from · (to/from)^(i/(points−1)), i = 0 .. points−1 (both ends exact).
void read_log_range(const std::string& where, const std::string& key, const YAML::Node& node,
                    SweepParameter& p) {
  LogRange r;
  read_map(where, key, node, "{from, to, points}", LogRange::fields(), r);
  if (!(r.from > 0) || !(r.to > 0) || r.points < 2 || r.points != std::round(r.points) ||
      r.points > 100000) {
    fail(where, node, key, "expected from > 0, to > 0 and an integer number of points >= 2");
  }
  p.form = SweepParameter::Form::kLog;
  p.from = r.from;
  p.to = r.to;
  p.count = static_cast<std::size_t>(r.points);
}

/// `parameters.<key>: {values: [..]}` or a range of either kind.
SweepParameter read_parameter(const std::string& where, const YAML::Node& key_node,
                              const YAML::Node& spec) {
  SweepParameter p;
  p.key = key_node.Scalar();
  p.line = yaml_line(key_node);
  const std::string prefix = "parameters." + p.key;
  if (!spec.IsMap() || spec.size() != 1) {
    fail(where, key_node, prefix,
         "expected one of {values: [..]}, {range: {from, to, step}}, "
         "{log_range: {from, to, points}}");
  }
  YamlFields fields(spec, where, prefix);
  const std::vector<std::string> forms = {"values", "range", "log_range"};
  fields.refuse_unknown(forms, one_of(forms));
  if (const YAML::Node values = spec["values"]) {
    if (!values.IsSequence() || values.size() == 0) {
      fail(where, values, prefix + ".values", "expected a non-empty list");
    }
    for (const YAML::Node& v : values) {
      if (!v.IsScalar()) fail(where, v, prefix + ".values", "expected scalar values");
      p.listed.push_back(v);
    }
    return p;
  }
  if (spec["range"]) {
    read_linear_range(where, prefix + ".range", spec["range"], p);
  } else {
    read_log_range(where, prefix + ".log_range", spec["log_range"], p);
  }
  return p;
}

/// name, description, base (which must exist) and trace, paths relative to `dir`.
void read_header(YamlFields& top, const std::filesystem::path& dir, SweepSpec& s) {
  SpecHeader header;
  parse_fields(top, header, SpecHeader::fields());
  s.name = header.name.empty() ? std::filesystem::path(s.file).stem().string() : header.name;
  s.base = dir / header.base;
  if (!std::filesystem::is_regular_file(s.base)) {
    top.fail("base", fmt::format("no such platform file '{}'", s.base.string()));
  }
  if (!header.trace.empty()) s.trace = dir / header.trace;
}

/// `workload:` (a map of the workload's parameters to scalar values), instead of a trace.
void read_workload(YamlFields& top, SweepSpec& s) {
  const YAML::Node workload = top.take("workload");
  if (!workload) return;
  if (!s.trace.empty()) {
    top.fail("workload",
             "give a trace or a workload, not both (a workload sweep traces its own points)");
  }
  if (!workload.IsMap()) top.fail("workload", "expected a map of workload parameters to values");
  // Checked by the tracer (WorkloadTracer::resolve), which knows the workload's keys.
  YamlFields fields(workload, s.file, "workload");
  s.workload = nlohmann::json::object();
  for (const auto& item : workload) {
    const std::string key = item.first.Scalar();
    if (!item.second.IsScalar()) fields.fail(key, "expected a scalar value");
    s.workload[key] = item.second.Scalar();
    s.workload_lines[key] = yaml_line(item.second);
  }
}

/// `parameters:`, the workload.* ones first; at most 10^4 workload points.
void read_parameters(YamlFields& top, SweepSpec& s) {
  const YAML::Node params = top.take("parameters");
  if (!params || !params.IsMap() || params.size() == 0) {
    top.fail("parameters",
             "expected a map of dotted platform keys to {values | range | log_range}");
  }
  std::vector<SweepParameter> platform_parameters;
  for (const auto& item : params) {
    SweepParameter p = read_parameter(s.file, item.first, item.second);
    if (!p.key.starts_with("workload.")) {
      platform_parameters.push_back(std::move(p));
      continue;
    }
    if (!s.traces_workload()) {
      fail(s.file, item.first, "parameters." + p.key,
           "a workload parameter needs a workload: section (the sweep then traces each "
           "workload point)");
    }
    s.parameters.push_back(std::move(p));
  }
  s.workload_parameters = s.parameters.size();
  double workload_points = 1;
  for (const SweepParameter& p : s.parameters) workload_points *= double(p.size());
  if (workload_points > kMaxWorkloadPoints) {
    top.fail("parameters",
             fmt::format("the workload.* parameters make {:.4g} workload points (at most 10^4: "
                         "each is a trace of the real pipeline)",
                         workload_points));
  }
  // A workload's precision is the design's: the platform computes at it (sweep_platform), so
  // backend.precision is not a parameter of its own then.
  const bool workload_precision =
      s.traces_workload() &&
      (s.workload.contains("precision") ||
       std::any_of(s.parameters.begin(), s.parameters.end(),
                   [](const SweepParameter& p) { return p.key == "workload.precision"; }));
  for (const auto& item : params) {
    if (workload_precision && item.first.Scalar() == "backend.precision") {
      fail(s.file, item.first, "parameters.backend.precision",
           "follows workload.precision (one precision per design: the units compute at the "
           "trace's); sweep workload.precision instead");
    }
  }
  for (SweepParameter& p : platform_parameters) s.parameters.push_back(std::move(p));
}

/// `sampling:` grid (the default), {random: {...}} or {nsga2: {...}}.
void read_sampling(YamlFields& top, SweepSpec& s) {
  const YAML::Node sampling = top.take("sampling");
  if (!sampling || (sampling.IsScalar() && sampling.Scalar() == "grid")) return;
  const auto one = [&](const char* form) {
    return sampling.IsMap() && sampling.size() == 1 && sampling[form] && sampling[form].IsMap();
  };
  if (one("random")) {
    read_map(s.file, "sampling.random", sampling["random"], "a map", random_sampling_fields(), s);
    s.random = true;
  } else if (one("nsga2")) {
    read_map(s.file, "sampling.nsga2", sampling["nsga2"], "a map", nsga2_sampling_fields(), s);
    const YamlFields fields(sampling["nsga2"], s.file, "sampling.nsga2");
    const double evaluations = double(s.population) * double(s.generations + 1);
    if (evaluations > kMaxSweepPoints) {
      fields.fail("", fmt::format("population x (generations + 1) = {:.4g} evaluations (more "
                                  "than 10^6)",
                                  evaluations));
    }
    s.nsga2 = true;
  } else {
    top.fail("sampling",
             "expected grid, {random: {samples: N, seed: S}} or {nsga2: {generations: G, "
             "population: P, seed: S}}");
  }
}

/// `objectives:` [{minimize: METRIC} | {maximize: METRIC}, ...], at least one.
void read_objectives(YamlFields& top, SweepSpec& s) {
  const YAML::Node objectives = top.take("objectives");
  if (!objectives || !objectives.IsSequence() || objectives.size() == 0) {
    top.fail("objectives", "expected a list of {minimize: METRIC} or {maximize: METRIC}");
  }
  for (std::size_t i = 0; i < objectives.size(); ++i) {
    const YAML::Node o = objectives[i];
    const std::string key = fmt::format("objectives[{}]", i);
    if (!o.IsMap() || o.size() != 1 || !(o["minimize"] || o["maximize"])) {
      fail(s.file, o, key, "expected {minimize: METRIC} or {maximize: METRIC}");
    }
    SweepObjective objective;
    objective.maximize = bool(o["maximize"]);
    const YAML::Node metric = objective.maximize ? o["maximize"] : o["minimize"];
    objective.metric = metric.IsScalar() ? metric.Scalar() : "";
    objective.line = yaml_line(metric);
    if (!is_sweep_metric(objective.metric)) {
      fail(s.file, metric, key,
           fmt::format("unknown metric '{}' (docs/SWEEPS.md lists them)", objective.metric));
    }
    s.objectives.push_back(objective);
  }
}

/// A relative constraint's `reference: {workload.KEY: VALUE, ...}`: the workload values that
/// make a point's reference (checked by the tracer when the sweep resolves its workload points).
void read_reference(const SweepSpec& s, const std::string& key, const YAML::Node& c,
                    SweepConstraint& constraint) {
  const YAML::Node reference = c["reference"];
  YamlFields fields(c, s.file, key);
  if (!reference) {
    fields.fail(
        "max_relative",
        "needs reference: {workload.KEY: VALUE, ...}, the workload point it is relative to");
  }
  if (!constraint.relative()) fields.fail("reference", "needs max_relative: X (a fraction)");
  if (c["min"] || c["max"]) {
    fields.fail(c["min"] ? "min" : "max",
                "a relative constraint takes max_relative and reference, not min or max");
  }
  if (!is_accuracy_metric(constraint.metric)) {
    fields.fail("metric", fmt::format("expected an accuracy metric (ate_rmse, ate_rmse_vio, "
                                      "ate_rmse_slam, ate_rmse_registration) with max_relative, "
                                      "got '{}'",
                                      constraint.metric));
  }
  if (!s.traces_workload()) {
    fields.fail("reference", "needs a workload: section (the reference is a workload point)");
  }
  if (!reference.IsMap() || reference.size() == 0) {
    fields.fail("reference", "expected a map of workload.* keys to values");
  }
  constraint.reference = nlohmann::json::object();
  for (const auto& item : reference) {
    const std::string k = item.first.Scalar();
    const std::string where = key + ".reference." + k;
    if (!k.starts_with("workload.") || k.size() == 9) {
      fail(s.file, item.first, where,
           "expected a workload.* key (the reference is a workload point)");
    }
    if (!item.second.IsScalar()) fail(s.file, item.second, where, "expected a scalar value");
    constraint.reference[k.substr(9)] = item.second.Scalar();
    constraint.reference_lines[k.substr(9)] = yaml_line(item.second);
  }
}

/// `constraints:` [{metric: METRIC, min: X, max: Y}, ...] (min, max or both), or relative:
/// [{metric: ACCURACY METRIC, max_relative: X, reference: {workload.KEY: VALUE}}].
void read_constraints(YamlFields& top, SweepSpec& s) {
  const YAML::Node constraints = top.take("constraints");
  if (!constraints) return;
  if (!constraints.IsSequence()) {
    top.fail("constraints", "expected a list of {metric, min and/or max}");
  }
  std::vector<std::string> keys = field_keys(ConstraintEntry::fields());
  keys.push_back("reference");
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const YAML::Node c = constraints[i];
    const std::string key = fmt::format("constraints[{}]", i);
    if (!c.IsMap() || !c["metric"] ||
        !(c["min"] || c["max"] || c["max_relative"] || c["reference"])) {
      fail(s.file, c, key,
           "expected {metric: METRIC, max: X} and/or min: X, or {metric: METRIC, max_relative: X, "
           "reference: {workload.KEY: VALUE}}");
    }
    YamlFields fields(c, s.file, key);
    fields.refuse_unknown(keys, one_of(keys));
    ConstraintEntry entry;
    parse_fields(fields, entry, ConstraintEntry::fields());
    if (!is_sweep_metric(entry.metric)) {
      YamlFields(c, s.file, key).fail("metric", fmt::format("unknown metric '{}'", entry.metric));
    }
    SweepConstraint constraint;
    constraint.metric = entry.metric;
    constraint.line = yaml_line(c);
    constraint.min = entry.min.value_or(constraint.min);
    constraint.max = entry.max.value_or(constraint.max);
    if (entry.min && entry.max && *entry.min > *entry.max) {
      YamlFields(c, s.file, key)
          .fail("min", fmt::format("min {} is above max {}: no value can meet it", *entry.min,
                                   *entry.max));
    }
    constraint.max_relative = entry.max_relative;
    if (constraint.relative() || c["reference"]) {
      read_reference(s, key, c, constraint);
      for (const SweepConstraint& other : s.constraints) {
        if (other.relative() && other.metric == constraint.metric) {
          YamlFields(c, s.file, key)
              .fail("metric", fmt::format("a second relative constraint on '{}' (one per metric)",
                                          constraint.metric));
        }
      }
    }
    s.constraints.push_back(constraint);
  }
}

/// The size first: a grid is enumerated one point at a time (SweepPoints), but more than 10^6
/// points is refused before any other work; a search indexes at most 2^53.
void check_grid_size(YamlFields& top, const SweepSpec& s) {
  if (!s.random && !s.nsga2 && grid_size(s) > kMaxSweepPoints) {
    top.fail("parameters",
             fmt::format("the grid has {:.4g} points (more than 10^6); use random sampling or a "
                         "search",
                         grid_size(s)));
  }
  if (s.nsga2 && grid_size(s) > kMaxSearchGrid) {
    top.fail("parameters", fmt::format("the grid has {:.4g} points (a search indexes at most 2^53)",
                                       grid_size(s)));
  }
  if (s.random && grid_size(s) > kMaxRandomGrid) {
    top.fail("parameters",
             fmt::format("the grid has {:.4g} points (random sampling indexes at most 2^126)",
                         grid_size(s)));
  }
}

/// Most values of one parameter checked on the base when the spec is read.
constexpr std::size_t kValuesCheckedAtRead = 256;

/// Every value must make a valid platform: each parameter's values checked on the base (loaded
/// once; each check on a copy of it, about 1 ms). A parameter of at most 256 values has every
/// value checked; a longer one 256 values spread evenly over it, both ends included, so that
/// reading a spec costs the same for any range size (issue 45); its other values are checked
/// when their point's platform is made, with the same one-line error naming the value.
void check_values_on_base(const SweepSpec& s) {
  const PlatformSource base = PlatformSource::load(s.base);
  for (std::size_t p = s.workload_parameters; p < s.parameters.size(); ++p) {
    const std::size_t n = s.parameters[p].size();
    const std::size_t checked = std::min(n, kValuesCheckedAtRead);
    for (std::size_t j = 0; j < checked; ++j) {
      SweepPoint point;
      point.choice.assign(s.parameters.size(), 0);
      // v_j = round(j (n−1)/(checked−1)): every index when checked == n, else both ends.
      point.choice[p] = checked == n ? j
                                     : static_cast<std::size_t>(std::llround(
                                           double(j) * double(n - 1) / double(checked - 1)));
      sweep_platform(s, point, base);
    }
  }
}

}  // namespace

SweepSpec SweepSpec::parse(const std::string& text, const std::string& where,
                           const std::filesystem::path& dir) {
  const YAML::Node root = load_yaml_map(text, where, "keys");
  YamlFields top(root, where, "");
  std::vector<std::string> keys = field_keys(SpecHeader::fields());
  keys.insert(keys.end(), kSectionKeys.begin(), kSectionKeys.end());
  top.refuse_unknown(keys, one_of(keys));
  SweepSpec s;
  s.file = where;
  read_header(top, dir, s);
  read_workload(top, s);
  read_parameters(top, s);
  read_sampling(top, s);
  read_objectives(top, s);
  read_constraints(top, s);
  check_grid_size(top, s);
  check_values_on_base(s);
  return s;
}

std::vector<ReferenceRow> sweep_spec_reference() {
  std::vector<ReferenceRow> rows;
  const auto add = [&rows](std::vector<ReferenceRow> more) {
    rows.insert(rows.end(), more.begin(), more.end());
  };
  add(reference_rows("", SpecHeader::fields(), {}, "Sweep spec (`sweeps/*.yaml`): top level"));
  add(reference_rows("parameters.<key>.range", LinearRange::fields(), {},
                     "Sweep spec: `parameters.<key>: {range: {...}}` (or `{values: [...]}`)"));
  add(reference_rows("parameters.<key>.log_range", LogRange::fields(), {},
                     "Sweep spec: `parameters.<key>: {log_range: {...}}`"));
  add(reference_rows("sampling.random", random_sampling_fields(), {},
                     "Sweep spec: `sampling: {random: {...}}` (default: `grid`)"));
  add(reference_rows("sampling.nsga2", nsga2_sampling_fields(), {},
                     "Sweep spec: `sampling: {nsga2: {...}}`"));
  add(reference_rows("constraints[]", ConstraintEntry::fields(), {},
                     "Sweep spec: `constraints: [{...}]` (min, max or both; or max_relative "
                     "with reference: {workload.KEY: VALUE, ...})"));
  return rows;
}

SweepSpec SweepSpec::load(const std::filesystem::path& path) {
  return parse(read_input_file(path, "sweep spec"), path.string(), path.parent_path());
}

}  // namespace edx::arch
