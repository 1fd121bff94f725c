// Sweep specs: expansion into design points, metrics and the Pareto front (reading a spec:
// sweep_spec.cpp).
#include "arch/sweep/sweep.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "arch/sweep/index_permutation.hpp"
#include "common/input_error.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {
namespace {

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

constexpr NamedMetric kAccuracyMetrics[] = {
    {"ate_rmse", "/all/ate_rmse_m"},
    {"ate_rmse_vio", "/vio/ate_rmse_m"},
    {"ate_rmse_slam", "/slam/ate_rmse_m"},
    {"ate_rmse_registration", "/registration/ate_rmse_m"},
};

bool is_accuracy_metric(const std::string& metric) {
  return std::any_of(std::begin(kAccuracyMetrics), std::end(kAccuracyMetrics),
                     [&](const NamedMetric& m) { return metric == m.name; });
}

double accuracy_metric(const nlohmann::json& accuracy, const std::string& metric) {
  for (const NamedMetric& m : kAccuracyMetrics) {
    if (metric != m.name) continue;
    const nlohmann::json::json_pointer ptr(m.pointer);
    // A mode that never ran, or ran with too few estimates for an alignment: undefined.
    return accuracy.contains(ptr) && accuracy.at(ptr).is_number()
               ? accuracy.at(ptr).get<double>()
               : std::numeric_limits<double>::quiet_NaN();
  }
  throw std::logic_error(fmt::format("'{}' is not an accuracy metric", metric));
}

double point_metric(const nlohmann::json& summary, const nlohmann::json& accuracy,
                    const std::string& metric) {
  return is_accuracy_metric(metric) ? accuracy_metric(accuracy, metric)
                                    : sweep_metric(summary, metric);
}

bool SweepSpec::needs_accuracy() const {
  return std::any_of(objectives.begin(), objectives.end(),
                     [](const SweepObjective& o) { return is_accuracy_metric(o.metric); }) ||
         std::any_of(constraints.begin(), constraints.end(),
                     [](const SweepConstraint& c) { return is_accuracy_metric(c.metric); });
}

bool is_sweep_metric(const std::string& metric) {
  if (is_accuracy_metric(metric)) return true;
  if (metric == "resources") return true;
  if (!metric.empty() && metric[0] == '/') {
    try {
      const nlohmann::json::json_pointer pointer(metric);
      return true;
    } catch (const nlohmann::json::exception&) {
      return false;  // "/a~2": '~' not followed by 0 or 1
    }
  }
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
    j[spec.parameters[p].key] = spec.parameters[p].text(choice[p]);
  }
  return j;
}

nlohmann::json SweepPoint::workload(const SweepSpec& spec) const {
  if (!spec.traces_workload()) return nullptr;
  nlohmann::json j = spec.workload;
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
    j[spec.parameters[p].key.substr(std::string_view("workload.").size())] =
        spec.parameters[p].text(choice[p]);
  }
  return j;
}

std::size_t SweepPoint::workload_index(const SweepSpec& spec) const {
  std::size_t index = 0;
  for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
    index = index * spec.parameters[p].size() + choice[p];
  }
  return index;
}

nlohmann::json SweepSpec::to_json() const {
  nlohmann::json params = nlohmann::json::object();
  for (const SweepParameter& p : parameters) params[p.key] = p.to_json();
  nlohmann::json obj = nlohmann::json::array(), con = nlohmann::json::array();
  for (const SweepObjective& o : objectives) {
    obj.push_back({{o.maximize ? "maximize" : "minimize", o.metric}});
  }
  for (const SweepConstraint& c : constraints) {
    nlohmann::json j = {{"metric", c.metric}};
    if (c.min > -1e300) j["min"] = c.min;
    if (c.max < 1e300) j["max"] = c.max;
    if (c.relative()) {
      j["max_relative"] = *c.max_relative;
      nlohmann::json reference = nlohmann::json::object();
      for (const auto& [key, value] : c.reference.items()) reference["workload." + key] = value;
      j["reference"] = reference;
    }
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

namespace {

/// Text of a generated value: integers without a decimal point (they must parse as int keys),
/// others to 4 significant digits (the text is the value the platform gets).
std::string generated_value_text(double v) {
  if (std::abs(v) < 9e15 && v == std::round(v)) return fmt::format("{}", std::int64_t(v));
  return fmt::format("{:.4g}", v);
}

}  // namespace

std::string SweepParameter::text(std::size_t i) const {
  if (i >= size()) throw std::out_of_range("SweepParameter::text");
  switch (form) {
    case Form::kListed:
      return listed[i].Scalar();
    case Form::kLinear:
      return generated_value_text(from + double(i) * step);
    case Form::kLog:
      return generated_value_text(
          i + 1 == count ? to : from * std::pow(to / from, double(i) / double(count - 1)));
  }
  return {};
}

nlohmann::json SweepParameter::to_json() const {
  switch (form) {
    case Form::kListed: {
      nlohmann::json texts = nlohmann::json::array();
      for (const YAML::Node& v : listed) texts.push_back(v.Scalar());
      return texts;
    }
    case Form::kLinear:
      return {{"range", {{"from", from}, {"to", to}, {"step", step}}}};
    case Form::kLog:
      return {{"log_range", {{"from", from}, {"to", to}, {"points", count}}}};
  }
  return nullptr;
}

double grid_size(const SweepSpec& spec) {
  double grid = 1;  // a double: the product of a few large counts must not wrap
  for (const SweepParameter& p : spec.parameters) grid *= double(p.size());
  return grid;
}

SweepPoints::SweepPoints(const SweepSpec& spec) : spec_(&spec) {
  const double grid = grid_size(spec);
  if (spec.nsga2) {
    if (grid > kMaxSearchGrid) {
      throw InputError(
          {spec.file}, "parameters",
          fmt::format("the grid has {:.4g} points (a search indexes at most 2^53)", grid));
    }
    size_ = static_cast<std::size_t>(grid);
    return;
  }
  if (!spec.random) {
    if (grid > kMaxSweepPoints) {
      throw InputError({spec.file}, "parameters",
                       fmt::format("the grid has {:.4g} points (more than 10^6); use random "
                                   "sampling or a search",
                                   grid));
    }
    size_ = static_cast<std::size_t>(grid);
    return;
  }
  // Distinct grid points without storing them: the first `samples` indices of a seeded
  // permutation of the grid (IndexPermutation); the grid itself is never enumerated.
  IndexPermutation::Index exact = 1;  // the grid's size, exact (a double rounds beyond 2^53)
  for (const SweepParameter& p : spec.parameters) {
    if (exact > IndexPermutation::kMaxSize / p.size()) {
      throw InputError({spec.file}, "parameters",
                       fmt::format("the grid has {:.4g} points (random sampling indexes at most "
                                   "2^126)",
                                   grid));
    }
    exact *= p.size();
  }
  size_ = static_cast<std::size_t>(std::min(double(spec.samples), grid));
  draws_.emplace(exact, spec.seed);
}

SweepPoint SweepPoints::at(std::size_t index) const {
  if (index >= size_) throw std::out_of_range("SweepPoints::at");
  SweepPoint point;
  point.index = index;
  point.choice.assign(spec_->parameters.size(), 0);
  IndexPermutation::Index rest = draws_ ? (*draws_)(index) : index;
  for (std::size_t p = spec_->parameters.size(); p-- > 0;) {  // last parameter fastest
    point.choice[p] = static_cast<std::size_t>(rest % spec_->parameters[p].size());
    rest /= spec_->parameters[p].size();
  }
  return point;
}

std::size_t SweepPoints::grid_index(const std::vector<std::size_t>& choice) const {
  std::size_t index = 0;
  for (std::size_t p = 0; p < spec_->parameters.size(); ++p) {
    index = index * spec_->parameters[p].size() + choice.at(p);
  }
  return index;
}

InputPlace parameter_value_place(const SweepSpec& spec, std::size_t p, std::size_t v) {
  const SweepParameter& param = spec.parameters.at(p);
  if (v >= param.size()) throw std::out_of_range("parameter_value_place");
  if (param.form == SweepParameter::Form::kListed) {
    if (const int line = yaml_line(param.listed[v]); line > 0) return {spec.file, line};
  }
  if (param.line == 0) return {spec.file};
  return {spec.file, param.line, fmt::format("parameters.{} = {}", param.key, param.text(v))};
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
    // A fresh node with the value's text (errors then take their place from the origin).
    source.set(param.key, YAML::Node(param.text(point.choice[p])),
               parameter_value_place(spec, p, point.choice[p]));
  }
  // A traced workload that states its precision makes the design's: the units compute at it
  // (backend.precision follows workload.precision; docs/SWEEPS.md "Precision").
  if (spec.traces_workload()) {
    const nlohmann::json workload = point.workload(spec);
    if (workload.contains("precision")) {
      std::optional<InputPlace> place;
      for (std::size_t p = 0; p < spec.workload_parameters; ++p) {
        if (spec.parameters[p].key == "workload.precision") {
          place = parameter_value_place(spec, p, point.choice[p]);
        }
      }
      const auto line = spec.workload_lines.find("precision");
      source.set("backend.precision", YAML::Node(workload.at("precision").get<std::string>()),
                 place
                     ? *place
                     : InputPlace{spec.file, line == spec.workload_lines.end() ? 0 : line->second});
    }
  }
  return Platform::parse(source);
}

}  // namespace edx::arch
