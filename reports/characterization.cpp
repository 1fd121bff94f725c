#include "reports/characterization.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "arch/system/system_model.hpp"
#include "common/config_fields.hpp"
#include "common/input_error.hpp"
#include "common/yaml_fields.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::reports {
namespace {

const std::vector<std::string>& scenario_names() {
  static const std::vector<std::string> names = {"indoor_unknown", "indoor_known",
                                                 "outdoor_unknown", "outdoor_known"};
  return names;
}

const FieldList<PaperCharacterizationPoint>& point_fields() {
  using C = PaperCharacterizationPoint;
  static const FieldList<C> list = {
      field("scenario", &C::scenario, "",
            "indoor_unknown, indoor_known, outdoor_unknown or "
            "outdoor_known"),
      field("backend", &C::backend, "", "vio, slam or registration"),
      optional_field("ate_m", &C::ate_m, "m", "the paper's ATE RMSE", Bounds::above(0),
                     {"unset", nullptr}),
      optional_field("fps", &C::fps, "FPS", "the paper's frame rate", Bounds::above(0),
                     {"unset", nullptr}),
  };
  return list;
}

const FieldList<PaperCharacterization::Scenario>& scenario_fields() {
  using C = PaperCharacterization::Scenario;
  static const FieldList<C> list = {
      field("scenario", &C::scenario, "", "the scenario"),
      field("least_error", &C::least_error, "", "the backend the paper finds most accurate"),
      field("fastest", &C::fastest, "", "the backend the paper finds fastest (\"\": not stated)"),
  };
  return list;
}

bool known(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// Reads a list under `key` of `top` into items by `fields`; each item's `scenario` (and the
/// `backends` keys) checked.
template <class Item>
std::vector<Item> read_list(YamlFields& top, const std::string& where, const std::string& key,
                            const FieldList<Item>& fields,
                            const std::vector<const char*>& backend_keys) {
  const YAML::Node list = top.take(key);
  if (!list || !list.IsSequence()) top.fail(key, "expected a list of maps");
  const std::vector<std::string> backends = {"vio", "slam", "registration"};
  std::vector<Item> items;
  for (const YAML::Node& node : list) {
    YamlFields item(node, where, "characterization." + key + "[]");
    item.refuse_unknown(field_keys(fields));
    Item value;
    parse_fields(item, value, fields);
    if (!known(scenario_names(), value.scenario)) {
      item.fail("scenario", fmt::format("expected indoor_unknown, indoor_known, outdoor_unknown "
                                        "or outdoor_known, got '{}'",
                                        value.scenario));
    }
    for (const char* k : backend_keys) {
      const YAML::Node b = node[k];
      if (b && !(b.IsScalar() && (b.Scalar().empty() || known(backends, b.Scalar())))) {
        item.fail(k, fmt::format("expected vio, slam or registration, got '{}'",
                                 YamlFields::described(b)));
      }
    }
    items.push_back(std::move(value));
  }
  return items;
}

double mean_of(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

/// Sample standard deviation (n − 1); 0 for fewer than two values.
double sd_of(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean_of(v);
  double sq = 0;
  for (double x : v) sq += (x - m) * (x - m);
  return std::sqrt(sq / static_cast<double>(v.size() - 1));
}

}  // namespace

std::vector<ReferenceRow> paper_characterization_reference() {
  const std::string file = "Paper targets (`reports/paper_targets.yaml`)";
  std::vector<ReferenceRow> rows = {reference_row("characterization", "source", FieldKind::kText,
                                                  "", std::string(), {}, {},
                                                  "where in the paper its statements are")};
  rows.back().group = file + ": `characterization:` (the paper's Sec. III statements)";
  for (ReferenceRow& row : reference_rows("characterization.points[]", point_fields(), {},
                                          file + ": `characterization: {points: [{...}]}`")) {
    rows.push_back(std::move(row));
  }
  for (ReferenceRow& row : reference_rows("characterization.scenarios[]", scenario_fields(), {},
                                          file + ": `characterization: {scenarios: [{...}]}`")) {
    rows.push_back(std::move(row));
  }
  return rows;
}

PaperCharacterization PaperCharacterization::load(const std::filesystem::path& targets_file) {
  const std::string where = targets_file.string();
  const YAML::Node root = load_yaml_map(read_input_file(targets_file, "targets file"), where,
                                        "'targets' and a 'tolerance'");
  PaperCharacterization paper;
  if (!root["characterization"]) return paper;
  YamlFields top(root["characterization"], where, "characterization");
  top.refuse_unknown({"source", "points", "scenarios"});
  if (const YAML::Node source = top.take("source"); source && source.IsScalar()) {
    paper.source = source.Scalar();
  }
  paper.points = read_list(top, where, "points", point_fields(), {"backend"});
  paper.scenarios =
      read_list(top, where, "scenarios", scenario_fields(), {"least_error", "fastest"});
  return paper;
}

CharacterizationStudy study_characterization(const std::vector<modes::CharacterizationRun>& runs,
                                             const arch::Platform& platform,
                                             const PaperCharacterization& paper) {
  CharacterizationStudy study;
  study.platform = platform.name;
  study.runs = runs;
  std::set<std::uint64_t> seeds;
  // Each run's frame rate: its trace on the platform, the baseline's e2e over the measured frames.
  for (const modes::CharacterizationRun& run : runs) {
    const trace::TraceReader reader(run.trace.string());
    const std::vector<trace::FrameTrace> frames = reader.read_all();
    arch::SystemSimOptions options;
    options.model = arch::SystemModelKind::kAnalytical;
    const arch::SystemResult r =
        arch::simulate_system(platform, frames, reader.meta(), run.trace.string(), options);
    std::vector<double> e2e;
    for (const arch::FrameResult& f : r.baseline.frames) {
      if (f.frame_id >= run.first_frame_id &&
          f.frame_id < run.first_frame_id + static_cast<std::int64_t>(run.frames)) {
        e2e.push_back(f.e2e_ms);
      }
    }
    const double mean = mean_of(e2e);
    study.run_fps.push_back(mean > 0 ? 1e3 / mean : 0.0);
    study.resolution = reader.meta().count("resolution") ? reader.meta().at("resolution") : "";
    study.frames = static_cast<int>(run.frames);
    seeds.insert(run.seed);
  }
  study.seeds.assign(seeds.begin(), seeds.end());
  // Per (scenario, backend), in the cells' order.
  for (const modes::CharacterizationCell& cell : modes::characterization_cells()) {
    CharacterizationPoint p;
    p.scenario = std::string(synthetic::to_string(cell.scenario));
    p.backend = trace::to_string(cell.backend);
    std::vector<double> ate, fps;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (runs[i].cell.scenario != cell.scenario || runs[i].cell.backend != cell.backend) continue;
      ++p.seeds;
      fps.push_back(study.run_fps[i]);
      if (runs[i].ate_rmse_m) {
        ate.push_back(*runs[i].ate_rmse_m);
      } else {
        ++p.seeds_without_ate;
      }
    }
    if (p.seeds == 0) continue;
    p.ate_mean_m = mean_of(ate);
    p.ate_sd_m = sd_of(ate);
    p.ate_max_m = ate.empty() ? 0.0 : *std::max_element(ate.begin(), ate.end());
    p.fps_mean = mean_of(fps);
    p.fps_sd = sd_of(fps);
    p.e2e_mean_ms = p.fps_mean > 0 ? 1e3 / p.fps_mean : 0.0;
    for (const PaperCharacterizationPoint& q : paper.points) {
      if (q.scenario == p.scenario && q.backend == p.backend) {
        p.paper_ate_m = q.ate_m;
        p.paper_fps = q.fps;
      }
    }
    study.points.push_back(std::move(p));
  }
  // Orderings: the least mean ATE (a backend without an ATE on some seed errs "most"), the most
  // mean FPS.
  for (const std::string& scenario : scenario_names()) {
    CharacterizationStudy::ScenarioResult s;
    s.scenario = scenario;
    double best_ate = 0, best_fps = 0;
    for (const CharacterizationPoint& p : study.points) {
      if (p.scenario != scenario) continue;
      if (p.seeds_without_ate == 0 && (s.least_error.empty() || p.ate_mean_m < best_ate)) {
        s.least_error = p.backend;
        best_ate = p.ate_mean_m;
      }
      if (s.fastest.empty() || p.fps_mean > best_fps) {
        s.fastest = p.backend;
        best_fps = p.fps_mean;
      }
    }
    for (const PaperCharacterization::Scenario& q : paper.scenarios) {
      if (q.scenario != scenario) continue;
      s.paper_least_error = q.least_error;
      s.paper_fastest = q.fastest;
    }
    if (!s.least_error.empty() || !s.fastest.empty()) study.scenarios.push_back(std::move(s));
  }
  return study;
}

nlohmann::json CharacterizationStudy::to_json() const {
  const auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json();
  };
  nlohmann::json runs_json = nlohmann::json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    nlohmann::json j = runs[i].to_json();
    j["fps"] = run_fps[i];
    runs_json.push_back(std::move(j));
  }
  nlohmann::json points_json = nlohmann::json::object();
  for (const CharacterizationPoint& p : points) {
    points_json[p.scenario][p.backend] = {{"seeds", p.seeds},
                                          {"seeds_without_ate", p.seeds_without_ate},
                                          {"ate_mean_m", p.ate_mean_m},
                                          {"ate_sd_m", p.ate_sd_m},
                                          {"ate_max_m", p.ate_max_m},
                                          {"fps_mean", p.fps_mean},
                                          {"fps_sd", p.fps_sd},
                                          {"e2e_mean_ms", p.e2e_mean_ms},
                                          {"paper_ate_m", optional(p.paper_ate_m)},
                                          {"paper_fps", optional(p.paper_fps)}};
  }
  nlohmann::json scenarios_json = nlohmann::json::object();
  for (const ScenarioResult& s : scenarios) {
    scenarios_json[s.scenario] = {{"least_error", s.least_error},
                                  {"fastest", s.fastest},
                                  {"paper_least_error", s.paper_least_error},
                                  {"paper_fastest", s.paper_fastest}};
  }
  return {{"platform", platform}, {"frames", frames},      {"resolution", resolution},
          {"seeds", seeds},       {"points", points_json}, {"scenarios", scenarios_json},
          {"runs", runs_json}};
}

nlohmann::json characterization_metrics(const nlohmann::json& study, const std::string& where) {
  nlohmann::json metrics = nlohmann::json::object();
  try {
    for (const auto& [scenario, backends] : study.at("points").items()) {
      for (const auto& [backend, p] : backends.items()) {
        metrics[scenario][backend] = {{"ate_m", p.at("ate_mean_m").get<double>()},
                                      {"fps", p.at("fps_mean").get<double>()}};
      }
    }
    for (const auto& [scenario, s] : study.at("scenarios").items()) {
      for (const char* kind : {"least_error", "fastest"}) {
        const std::string paper = s.at(std::string("paper_") + kind).get<std::string>();
        if (paper.empty()) continue;
        metrics[scenario][std::string(kind) + "_matches"] =
            s.at(kind).get<std::string>() == paper ? 1.0 : 0.0;
      }
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format(
        "{}: expected the characterization.json of edx characterize ({})", where, e.what()));
  }
  return metrics;
}

std::string format_characterization(const CharacterizationStudy& s) {
  std::string text =
      fmt::format("characterization on {}'s baseline host, {} frames a run at {}, seeds {}\n",
                  s.platform, s.frames, s.resolution, fmt::join(s.seeds, ", "));
  text += fmt::format("{:<16} {:<13} {:>10} {:>8} {:>8} {:>9} {:>8} {:>8}\n", "scenario", "backend",
                      "ATE m", "sd", "paper", "FPS", "sd", "paper");
  const auto opt = [](const std::optional<double>& v) {
    return v ? fmt::format("{:.2f}", *v) : std::string("-");
  };
  for (const CharacterizationPoint& p : s.points) {
    const std::string ate =
        p.seeds_without_ate == p.seeds
            ? std::string("none")
            : fmt::format("{:.3f}{}", p.ate_mean_m, p.seeds_without_ate > 0 ? "*" : "");
    text += fmt::format("{:<16} {:<13} {:>10} {:>8.3f} {:>8} {:>9.2f} {:>8.2f} {:>8}\n", p.scenario,
                        p.backend, ate, p.ate_sd_m, opt(p.paper_ate_m), p.fps_mean, p.fps_sd,
                        opt(p.paper_fps));
  }
  text += "(* some seeds had too few estimates for an ATE; 'none': no seed had)\n";
  text += fmt::format("{:<16} {:<13} {:<13} {:<13} {:<13}\n", "scenario", "least error", "paper",
                      "fastest", "paper");
  for (const CharacterizationStudy::ScenarioResult& r : s.scenarios) {
    const auto or_dash = [](const std::string& v) { return v.empty() ? std::string("-") : v; };
    text += fmt::format("{:<16} {:<13} {:<13} {:<13} {:<13}\n", r.scenario, or_dash(r.least_error),
                        or_dash(r.paper_least_error), or_dash(r.fastest), or_dash(r.paper_fastest));
  }
  return text;
}

}  // namespace edx::reports
