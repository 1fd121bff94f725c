// Sweep specs: parsing, expansion into design points, metrics and the Pareto front.
#include "arch/sweep/sweep.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

int line_of(const YAML::Node& node) { return node.Mark().is_null() ? 0 : node.Mark().line + 1; }

/// "where:line: key: message" (the line left out when unknown).
[[noreturn]] void fail(const std::string& where, const YAML::Node& node, const std::string& key,
                       const std::string& message) {
  const int line = node ? line_of(node) : 0;
  throw std::runtime_error(line > 0 ? fmt::format("{}:{}: {}: {}", where, line, key, message)
                                    : fmt::format("{}: {}: {}", where, key, message));
}

double number(const std::string& where, const YAML::Node& node, const std::string& key) {
  double v = 0;
  if (!node || !node.IsScalar() || !YAML::convert<double>::decode(node, v) || !std::isfinite(v)) {
    fail(where, node, key,
         fmt::format("expected a number, got '{}'", node && node.IsScalar() ? node.Scalar()
                                                    : node                  ? "a list or map"
                                                                            : "nothing"));
  }
  return v;
}

/// Text of a generated value: integers without a decimal point (they must parse as int keys),
/// others to 4 significant digits (the text is the value the platform gets).
std::string value_text(double v) {
  if (std::abs(v) < 9e15 && v == std::round(v)) return fmt::format("{}", std::int64_t(v));
  return fmt::format("{:.4g}", v);  // generated values: 4 significant digits
}

void check_keys(const std::string& where, const YAML::Node& map, const std::string& prefix,
                std::initializer_list<const char*> allowed) {
  for (const auto& item : map) {
    const std::string key = item.first.Scalar();
    if (std::find_if(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }) ==
        allowed.end()) {
      fail(where, item.first, prefix + "." + key,
           fmt::format("unknown key (expected one of: {})", fmt::join(allowed, ", ")));
    }
  }
}

SweepParameter parse_parameter(const std::string& where, const YAML::Node& key_node,
                               const YAML::Node& spec) {
  SweepParameter p;
  p.key = key_node.Scalar();
  p.line = line_of(key_node);
  const std::string prefix = "parameters." + p.key;
  if (!spec.IsMap() || spec.size() != 1) {
    fail(where, key_node, prefix,
         "expected one of {values: [..]}, {range: {from, to, step}}, "
         "{log_range: {from, to, points}}");
  }
  check_keys(where, spec, prefix, {"values", "range", "log_range"});
  std::vector<double> generated;
  if (const YAML::Node values = spec["values"]) {
    if (!values.IsSequence() || values.size() == 0) {
      fail(where, values, prefix + ".values", "expected a non-empty list");
    }
    for (const YAML::Node& v : values) {
      if (!v.IsScalar()) fail(where, v, prefix + ".values", "expected scalar values");
      p.values.push_back(v);
      p.texts.push_back(v.Scalar());
    }
    return p;
  }
  if (const YAML::Node range = spec["range"]) {
    if (!range.IsMap()) fail(where, range, prefix + ".range", "expected {from, to, step}");
    check_keys(where, range, prefix + ".range", {"from", "to", "step"});
    const double from =
        number(where, range["from"] ? range["from"] : range, prefix + ".range.from");
    const double to = number(where, range["to"] ? range["to"] : range, prefix + ".range.to");
    const double step =
        number(where, range["step"] ? range["step"] : range, prefix + ".range.step");
    if (!(step > 0) || to < from) {
      fail(where, range, prefix + ".range", "expected step > 0 and to >= from");
    }
    // from + i·step for i = 0 .. floor((to − from)/step) (a relative 1e-9 slack keeps `to`).
    // The count as a double first: (to - from) / step may overflow any integer (or be inf).
    const double count = std::floor((to - from) / step * (1 + 1e-12) + 1e-9);
    if (!(count < 100000)) {
      fail(where, range, prefix + ".range",
           std::isfinite(count) ? fmt::format("{:.4g} values (at most 100000)", count + 1)
                                : std::string("more than 100000 values"));
    }
    const auto n = static_cast<std::size_t>(count);
    for (std::size_t i = 0; i <= n; ++i) generated.push_back(from + double(i) * step);
  } else {
    const YAML::Node log_range = spec["log_range"];
    if (!log_range.IsMap())
      fail(where, log_range, prefix + ".log_range", "expected {from, to, points}");
    check_keys(where, log_range, prefix + ".log_range", {"from", "to", "points"});
    const double from = number(where, log_range["from"] ? log_range["from"] : log_range,
                               prefix + ".log_range.from");
    const double to =
        number(where, log_range["to"] ? log_range["to"] : log_range, prefix + ".log_range.to");
    const double points = number(where, log_range["points"] ? log_range["points"] : log_range,
                                 prefix + ".log_range.points");
    if (!(from > 0) || !(to > 0) || points < 2 || points != std::round(points) || points > 100000) {
      fail(where, log_range, prefix + ".log_range",
           "expected from > 0, to > 0 and an integer number of points >= 2");
    }
    // Geometric: from · (to/from)^(i/(points−1)), i = 0 .. points−1 (both ends exact).
    const auto n = static_cast<std::size_t>(points);
    for (std::size_t i = 0; i < n; ++i) {
      generated.push_back(i + 1 == n ? to : from * std::pow(to / from, double(i) / double(n - 1)));
    }
  }
  for (double v : generated) {
    p.texts.push_back(value_text(v));
    p.values.push_back(YAML::Node(p.texts.back()));
  }
  return p;
}

/// splitmix64 (Steele, Lea and Flood 2014): a fixed, portable stream for random sampling.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

struct NamedMetric {
  const char* name;
  const char* pointer;
};

constexpr NamedMetric kMetrics[] = {
    {"e2e_latency_mean", "/accelerated/modes/all/e2e_ms/mean"},
    {"e2e_latency_p99", "/accelerated/modes/all/e2e_ms/p99"},
    {"e2e_latency_sd", "/accelerated/modes/all/e2e_ms/sd"},
    {"frontend_latency_mean", "/accelerated/modes/all/frontend_ms/mean"},
    {"backend_latency_mean", "/accelerated/modes/all/backend_ms/mean"},
    {"fps", "/accelerated/fps_with_pipelining"},
    {"fps_without_pipelining", "/accelerated/fps_without_pipelining"},
    {"energy_mean", "/accelerated/modes/all/energy_j/mean"},
    {"stream_latency_mean", "/accelerated/stream/latency_ms/mean"},
    {"stream_latency_p99", "/accelerated/stream/latency_ms/p99"},
    {"dropped", "/accelerated/stream/dropped"},
    {"stream_energy", "/accelerated/stream/energy_j"},
    {"e2e_speedup", "/comparison/all/e2e_speedup"},
    {"lut", "/resources/total/lut"},
    {"ff", "/resources/total/ff"},
    {"dsp", "/resources/total/dsp"},
    {"bram", "/resources/total/bram_blocks"},
    {"lut_util", "/resources/utilization/lut"},
    {"ff_util", "/resources/utilization/ff"},
    {"dsp_util", "/resources/utilization/dsp"},
    {"bram_util", "/resources/utilization/bram_blocks"},
};

}  // namespace

bool is_sweep_metric(const std::string& metric) {
  if (metric == "resources" || (!metric.empty() && metric[0] == '/')) return true;
  return std::any_of(std::begin(kMetrics), std::end(kMetrics),
                     [&](const NamedMetric& m) { return metric == m.name; });
}

double sweep_metric(const nlohmann::json& summary, const std::string& metric) {
  if (metric == "resources") {
    // The largest utilization of the four resources (1 = the whole device).
    double worst = 0;
    for (const char* m : {"lut_util", "ff_util", "dsp_util", "bram_util"}) {
      worst = std::max(worst, sweep_metric(summary, m));
    }
    return worst;
  }
  std::string pointer = metric;
  for (const NamedMetric& m : kMetrics) {
    if (metric == m.name) pointer = m.pointer;
  }
  if (pointer.empty() || pointer[0] != '/') {
    throw std::runtime_error(fmt::format("unknown metric '{}'", metric));
  }
  const nlohmann::json::json_pointer ptr(pointer);
  if (!summary.contains(ptr) || !summary.at(ptr).is_number()) {
    throw std::runtime_error(
        fmt::format("metric '{}': the run summary has no number at {}", metric, pointer));
  }
  return summary.at(ptr).get<double>();
}

std::vector<std::size_t> pareto_front(const std::vector<std::vector<double>>& values,
                                      const std::vector<bool>& maximize) {
  const auto better_or_equal = [&](double a, double b, std::size_t k) {
    return maximize[k] ? a >= b : a <= b;
  };
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < values.size(); ++i) {
    bool dominated = false;
    for (std::size_t j = 0; j < values.size() && !dominated; ++j) {
      if (i == j) continue;
      bool all = true, strictly = false;
      for (std::size_t k = 0; k < maximize.size(); ++k) {
        all = all && better_or_equal(values[j][k], values[i][k], k);
        strictly = strictly || values[j][k] != values[i][k];
      }
      dominated = all && strictly;
    }
    if (!dominated) front.push_back(i);
  }
  return front;
}

nlohmann::json SweepPoint::parameters(const SweepSpec& spec) const {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t p = 0; p < spec.parameters.size(); ++p) {
    j[spec.parameters[p].key] = spec.parameters[p].texts[choice[p]];
  }
  return j;
}

nlohmann::json SweepPoint::workload(const SweepSpec& spec) const {
  if (!spec.traces_workload()) return nullptr;
  nlohmann::json j = spec.workload;
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
    j[spec.parameters[p].key.substr(std::string_view("workload.").size())] =
        spec.parameters[p].texts[choice[p]];
  }
  return j;
}

std::size_t SweepPoint::workload_index(const SweepSpec& spec) const {
  std::size_t index = 0;
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
    index = index * spec.parameters[p].values.size() + choice[p];
  }
  return index;
}

nlohmann::json SweepSpec::to_json() const {
  nlohmann::json params = nlohmann::json::object();
  for (const SweepParameter& p : parameters) params[p.key] = p.texts;
  nlohmann::json obj = nlohmann::json::array(), con = nlohmann::json::array();
  for (const SweepObjective& o : objectives) {
    obj.push_back({{o.maximize ? "maximize" : "minimize", o.metric}});
  }
  for (const SweepConstraint& c : constraints) {
    nlohmann::json j = {{"metric", c.metric}};
    if (c.min > -1e300) j["min"] = c.min;
    if (c.max < 1e300) j["max"] = c.max;
    con.push_back(j);
  }
  nlohmann::json sampling = "grid";
  if (random) sampling = {{"random", {{"samples", samples}, {"seed", seed}}}};
  if (nsga2) {
    sampling = {
        {"nsga2", {{"generations", generations}, {"population", population}, {"seed", seed}}}};
  }
  nlohmann::json j = {{"name", name},         {"base", base.string()}, {"trace", trace.string()},
                      {"parameters", params}, {"sampling", sampling},  {"objectives", obj},
                      {"constraints", con}};
  if (traces_workload()) j["workload"] = workload;
  return j;
}

SweepSpec SweepSpec::parse(const std::string& text, const std::string& where,
                           const std::filesystem::path& dir) {
  const YAML::Node root = load_yaml_map(text, where, "keys");
  check_keys(where, root, "sweep",
             {"name", "description", "base", "trace", "workload", "parameters", "sampling",
              "objectives", "constraints"});
  SweepSpec s;
  s.file = where;
  const auto text_of = [&](const char* key, bool required) -> std::string {
    const YAML::Node n = root[key];
    if (!n) {
      if (required) fail(where, root, key, "required");
      return {};
    }
    if (!n.IsScalar() || n.Scalar().empty()) fail(where, n, key, "expected a text value");
    return n.Scalar();
  };
  s.name = text_of("name", false);
  if (s.name.empty()) s.name = std::filesystem::path(where).stem().string();
  s.base = dir / text_of("base", true);
  if (!std::filesystem::is_regular_file(s.base)) {
    fail(where, root["base"], "base", fmt::format("no such platform file '{}'", s.base.string()));
  }
  if (const std::string trace = text_of("trace", false); !trace.empty()) s.trace = dir / trace;
  if (const YAML::Node workload = root["workload"]) {
    if (root["trace"]) {
      fail(where, workload, "workload",
           "give a trace or a workload, not both (a workload sweep traces its own points)");
    }
    if (!workload.IsMap()) {
      fail(where, workload, "workload", "expected a map of workload parameters to values");
    }
    s.workload = nlohmann::json::object();
    for (const auto& item : workload) {
      if (!item.second.IsScalar()) {
        fail(where, item.second, "workload." + item.first.Scalar(), "expected a scalar value");
      }
      s.workload[item.first.Scalar()] = item.second.Scalar();
    }
  }

  const YAML::Node params = root["parameters"];
  if (!params || !params.IsMap() || params.size() == 0) {
    fail(where, params ? params : root, "parameters",
         "expected a map of dotted platform keys to {values | range | log_range}");
  }
  std::vector<SweepParameter> platform_parameters;
  for (const auto& item : params) {
    SweepParameter p = parse_parameter(where, item.first, item.second);
    if (!p.key.starts_with("workload.")) {
      platform_parameters.push_back(std::move(p));
      continue;
    }
    if (!s.traces_workload()) {
      fail(where, item.first, "parameters." + p.key,
           "a workload parameter needs a workload: section (the sweep then traces each "
           "workload point)");
    }
    s.parameters.push_back(std::move(p));
  }
  s.workload_parameters = s.parameters.size();
  double workload_points = 1;
  for (const SweepParameter& p : s.parameters) workload_points *= double(p.values.size());
  if (workload_points > kMaxWorkloadPoints) {
    fail(where, params, "parameters",
         fmt::format("the workload.* parameters make {:.4g} workload points (at most 10^4: each "
                     "is a trace of the real pipeline)",
                     workload_points));
  }
  for (SweepParameter& p : platform_parameters) s.parameters.push_back(std::move(p));

  if (const YAML::Node sampling = root["sampling"]) {
    if (sampling.IsScalar() && sampling.Scalar() == "grid") {
    } else if (sampling.IsMap() && sampling.size() == 1 && sampling["random"] &&
               sampling["random"].IsMap()) {
      const YAML::Node r = sampling["random"];
      check_keys(where, r, "sampling.random", {"samples", "seed"});
      const double samples =
          number(where, r["samples"] ? r["samples"] : r, "sampling.random.samples");
      const double seed = r["seed"] ? number(where, r["seed"], "sampling.random.seed") : 1.0;
      if (samples < 1 || samples != std::round(samples) || samples > kMaxSweepPoints) {
        fail(where, r["samples"], "sampling.random.samples", "expected an integer from 1 to 10^6");
      }
      // 2^53: the largest range in which every integer is a double (a YAML number is read as
      // one), far inside std::uint64_t.
      if (seed < 0 || seed != std::round(seed) || seed > 9007199254740992.0) {
        fail(where, r["seed"], "sampling.random.seed", "expected an integer from 0 to 2^53");
      }
      s.random = true;
      s.samples = static_cast<std::size_t>(samples);
      s.seed = static_cast<std::uint64_t>(seed);
    } else if (sampling.IsMap() && sampling.size() == 1 && sampling["nsga2"] &&
               sampling["nsga2"].IsMap()) {
      const YAML::Node n = sampling["nsga2"];
      check_keys(where, n, "sampling.nsga2", {"generations", "population", "seed"});
      const double generations =
          number(where, n["generations"] ? n["generations"] : n, "sampling.nsga2.generations");
      const double population =
          number(where, n["population"] ? n["population"] : n, "sampling.nsga2.population");
      const double seed = n["seed"] ? number(where, n["seed"], "sampling.nsga2.seed") : 1.0;
      if (generations < 1 || generations != std::round(generations) || generations > 10000) {
        fail(where, n["generations"], "sampling.nsga2.generations",
             "expected an integer from 1 to 10000");
      }
      // pagmo's NSGA-II pairs parents four at a time: at least 8, a multiple of 4.
      if (population < 8 || population != std::round(population) || population > 10000 ||
          std::fmod(population, 4) != 0) {
        fail(where, n["population"], "sampling.nsga2.population",
             "expected a multiple of 4 from 8 to 10000");
      }
      if (population * (generations + 1) > kMaxSweepPoints) {
        fail(where, n, "sampling.nsga2",
             fmt::format("population x (generations + 1) = {:.4g} evaluations (more than 10^6)",
                         population * (generations + 1)));
      }
      // pagmo seeds are unsigned 32-bit integers.
      if (seed < 0 || seed != std::round(seed) || seed > 4294967295.0) {
        fail(where, n["seed"], "sampling.nsga2.seed", "expected an integer from 0 to 2^32 - 1");
      }
      if (s.workload_parameters > 0) {
        fail(where, n, "sampling.nsga2",
             "a search varies platform parameters only (use grid or random sampling with "
             "workload.* parameters)");
      }
      s.nsga2 = true;
      s.generations = static_cast<std::size_t>(generations);
      s.population = static_cast<std::size_t>(population);
      s.seed = static_cast<std::uint64_t>(seed);
    } else {
      fail(where, sampling, "sampling",
           "expected grid, {random: {samples: N, seed: S}} or {nsga2: {generations: G, "
           "population: P, seed: S}}");
    }
  }

  const YAML::Node objectives = root["objectives"];
  if (!objectives || !objectives.IsSequence() || objectives.size() == 0) {
    fail(where, objectives ? objectives : root, "objectives",
         "expected a list of {minimize: METRIC} or {maximize: METRIC}");
  }
  for (std::size_t i = 0; i < objectives.size(); ++i) {
    const YAML::Node o = objectives[i];
    const std::string key = fmt::format("objectives[{}]", i);
    if (!o.IsMap() || o.size() != 1 || !(o["minimize"] || o["maximize"])) {
      fail(where, o, key, "expected {minimize: METRIC} or {maximize: METRIC}");
    }
    SweepObjective obj;
    obj.maximize = bool(o["maximize"]);
    const YAML::Node m = obj.maximize ? o["maximize"] : o["minimize"];
    obj.metric = m.IsScalar() ? m.Scalar() : "";
    if (!is_sweep_metric(obj.metric)) {
      fail(where, m, key,
           fmt::format("unknown metric '{}' (docs/SWEEPS.md lists them)", obj.metric));
    }
    s.objectives.push_back(obj);
  }
  if (const YAML::Node constraints = root["constraints"]) {
    if (!constraints.IsSequence()) {
      fail(where, constraints, "constraints", "expected a list of {metric, min and/or max}");
    }
    for (std::size_t i = 0; i < constraints.size(); ++i) {
      const YAML::Node c = constraints[i];
      const std::string key = fmt::format("constraints[{}]", i);
      if (!c.IsMap() || !c["metric"] || !(c["min"] || c["max"])) {
        fail(where, c, key, "expected {metric: METRIC, max: X} and/or min: X");
      }
      check_keys(where, c, key, {"metric", "min", "max"});
      SweepConstraint con;
      con.metric = c["metric"].IsScalar() ? c["metric"].Scalar() : "";
      if (!is_sweep_metric(con.metric)) {
        fail(where, c["metric"], key + ".metric", fmt::format("unknown metric '{}'", con.metric));
      }
      if (c["min"]) con.min = number(where, c["min"], key + ".min");
      if (c["max"]) con.max = number(where, c["max"], key + ".max");
      s.constraints.push_back(con);
    }
  }
  // The size first: a grid is enumerated one point at a time (SweepPoints), but more than
  // 10^6 points is refused before any other work.
  if (!s.random && !s.nsga2 && grid_size(s) > kMaxSweepPoints) {
    fail(where, params, "parameters",
         fmt::format("the grid has {:.4g} points (more than 10^6); use random sampling or a "
                     "search",
                     grid_size(s)));
  }
  if (s.nsga2 && grid_size(s) > kMaxSearchGrid) {
    fail(where, params, "parameters",
         fmt::format("the grid has {:.4g} points (a search indexes at most 2^53)", grid_size(s)));
  }
  // Every point must make a valid platform: check each parameter's values on the base (loaded
  // once; each check on a copy of it).
  const PlatformSource base = PlatformSource::load(s.base);
  for (std::size_t p = s.workload_parameters; p < s.parameters.size(); ++p) {
    for (std::size_t v = 0; v < s.parameters[p].values.size(); ++v) {
      SweepPoint point;
      point.choice.assign(s.parameters.size(), 0);
      point.choice[p] = v;
      sweep_platform(s, point, base);
    }
  }
  return s;
}

SweepSpec SweepSpec::load(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read the sweep spec", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path.string(), path.parent_path());
}

double grid_size(const SweepSpec& spec) {
  double grid = 1;  // a double: the product of a few large counts must not wrap
  for (const SweepParameter& p : spec.parameters) grid *= double(p.values.size());
  return grid;
}

SweepPoints::SweepPoints(const SweepSpec& spec) : spec_(&spec) {
  const double grid = grid_size(spec);
  if (spec.nsga2) {
    if (grid > kMaxSearchGrid) {
      throw std::runtime_error(
          fmt::format("{}: parameters: the grid has {:.4g} points (a search indexes at most 2^53)",
                      spec.file, grid));
    }
    size_ = static_cast<std::size_t>(grid);
    return;
  }
  if (!spec.random) {
    if (grid > kMaxSweepPoints) {
      throw std::runtime_error(fmt::format(
          "{}: parameters: the grid has {:.4g} points (more than 10^6); use random sampling or a "
          "search",
          spec.file, grid));
    }
    size_ = static_cast<std::size_t>(grid);
    return;
  }
  // Distinct grid points: one value per parameter drawn uniformly (top 53 bits of the stream
  // scaled to the count), duplicates drawn again. At most 10^6 (the spec's cap), so the draws
  // are kept; the grid itself is never enumerated.
  const auto want = static_cast<std::size_t>(std::min(double(spec.samples), grid));
  std::uint64_t state = spec.seed;
  std::set<std::vector<std::size_t>> seen;
  while (drawn_.size() < want) {
    std::vector<std::size_t> choice;
    for (const SweepParameter& p : spec.parameters) {
      const double u = double(splitmix64(state) >> 11) * 0x1.0p-53;
      choice.push_back(std::min(p.values.size() - 1, std::size_t(u * double(p.values.size()))));
    }
    if (seen.insert(choice).second) drawn_.push_back(std::move(choice));
  }
  size_ = drawn_.size();
}

SweepPoint SweepPoints::at(std::size_t index) const {
  if (index >= size_) throw std::out_of_range("SweepPoints::at");
  SweepPoint point;
  point.index = index;
  if (spec_->random) {
    point.choice = drawn_[index];
    return point;
  }
  point.choice.assign(spec_->parameters.size(), 0);
  std::size_t rest = index;
  for (std::size_t p = spec_->parameters.size(); p-- > 0;) {  // last parameter fastest
    point.choice[p] = rest % spec_->parameters[p].values.size();
    rest /= spec_->parameters[p].values.size();
  }
  return point;
}

std::size_t SweepPoints::grid_index(const std::vector<std::size_t>& choice) const {
  std::size_t index = 0;
  for (std::size_t p = 0; p < spec_->parameters.size(); ++p) {
    index = index * spec_->parameters[p].values.size() + choice.at(p);
  }
  return index;
}

Platform sweep_platform(const SweepSpec& spec, const SweepPoint& point) {
  return sweep_platform(spec, point, PlatformSource::load(spec.base));
}

Platform sweep_platform(const SweepSpec& spec, const SweepPoint& point,
                        const PlatformSource& base) {
  // A deep copy of the base, and copies of the spec's values: nodes of two documents are
  // never linked, since yaml-cpp then merges their memory and keeps both alive (issue 21: a
  // 10^9-point sweep took GBs before its first point).
  PlatformSource source = base;
  source.root = YAML::Clone(base.root);
  for (std::size_t p = spec.workload_parameters; p < spec.parameters.size(); ++p) {
    const SweepParameter& param = spec.parameters[p];
    // A fresh node with the value's text (errors then take their line from the origin: the
    // value's line in the spec, or the key's for a generated value).
    const YAML::Node& value = param.values[point.choice[p]];
    std::string origin = spec.file;
    if (!value.Mark().is_null()) {
      origin = fmt::format("{}:{}", spec.file, value.Mark().line + 1);
    } else if (param.line > 0) {
      origin = fmt::format("{}:{} (parameters.{} = {})", spec.file, param.line, param.key,
                           param.texts[point.choice[p]]);
    }
    source.set(param.key, value.IsScalar() ? YAML::Node(value.Scalar()) : YAML::Clone(value),
               origin);
  }
  return Platform::parse(source);
}

}  // namespace edx::arch
