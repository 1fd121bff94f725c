#include "reports/metrics.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "arch/kernels/kernels.hpp"

namespace edx::reports {
namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

/// The keys of a dotted metric path, "a.b.c" -> {a, b, c}.
std::vector<std::string> path_keys(const std::string& path) {
  std::vector<std::string> keys;
  for (std::size_t start = 0;;) {
    const std::size_t dot = path.find('.', start);
    keys.push_back(path.substr(start, dot == std::string::npos ? dot : dot - start));
    if (dot == std::string::npos) return keys;
    start = dot + 1;
  }
}

}  // namespace

std::vector<std::string> run_modes(const RunData& run) {
  std::set<std::string> present;
  for (const FrameRow& f : run.frame_rows) present.insert(f.mode);
  std::vector<std::string> modes;
  for (const char* m : {"registration", "vio", "slam", "none"}) {
    if (present.erase(m)) modes.push_back(m);
  }
  for (const std::string& m : present) modes.push_back(m);  // unknown modes last
  return modes;
}

std::vector<BackendBreakdown> backend_breakdown(const RunData& run) {
  std::set<std::string> kernel_names;
  for (const OffloadRow& o : run.offload) kernel_names.insert(o.kernel);
  std::map<std::int64_t, std::string> mode_of;  // frame_id -> mode
  for (const FrameRow& f : run.frame_rows) mode_of[f.frame_id] = f.mode;
  std::vector<std::string> modes = run_modes(run);
  modes.push_back("all");

  std::vector<BackendBreakdown> out;
  for (const std::string& mode : modes) {
    const auto in_mode = [&](std::int64_t frame_id) {
      return mode == "all" || mode_of[frame_id] == mode;
    };
    std::size_t frames = 0;
    double backend_base = 0;
    for (const FrameRow& f : run.frame_rows) {
      if (f.variant == "baseline" && in_mode(f.frame_id)) {
        ++frames;
        backend_base += f.backend_ms;
      }
    }
    if (frames == 0) continue;
    std::map<std::string, double> host, accel;
    for (const OffloadRow& o : run.offload) {
      if (!in_mode(o.frame_id)) continue;
      host[o.kernel] += o.host_ms;
      accel[o.kernel] += o.offloaded ? o.accel_ms : o.host_ms;
    }
    double kernels_host = 0;
    for (const auto& [k, v] : host) kernels_host += v;
    for (const char* variant : {"baseline", "accelerated"}) {
      BackendBreakdown b{mode, variant, frames, {}};
      const bool base = std::string(variant) == "baseline";
      for (const std::string& k : kernel_names) {
        b.parts.emplace_back(k, (base ? host[k] : accel[k]) / double(frames));
      }
      b.parts.emplace_back("other", (backend_base - kernels_host) / double(frames));
      out.push_back(std::move(b));
    }
  }
  return out;
}

nlohmann::json run_metrics(const RunData& run) {
  nlohmann::json derived = {{"kernels", nlohmann::json::object()},
                            {"schedule", nlohmann::json::object()},
                            {"backend", nlohmann::json::object()}};
  std::map<std::string, std::pair<double, double>> sums;  // kernel -> (Σ host, Σ accel), fitting
  std::map<std::string, std::pair<int, int>> counts;      // kernel -> (invocations, fitting)
  for (const OffloadRow& o : run.offload) {
    ++counts[o.kernel].first;
    if (!o.fits_spm || !std::isfinite(o.accel_ms)) continue;
    ++counts[o.kernel].second;
    sums[o.kernel].first += o.host_ms;
    sums[o.kernel].second += o.accel_ms;
  }
  for (const auto& [k, c] : counts) {
    const auto [host, accel] = sums[k];
    derived["kernels"][k] = {
        {"invocations", c.first},
        {"fitting", c.second},
        {"host_ms", host},
        {"accel_ms", accel},
        {"speedup", c.second > 0 && accel > 0 ? nlohmann::json(host / accel) : nullptr},
        {"latency_reduction",
         c.second > 0 && host > 0 ? nlohmann::json(1 - accel / host) : nullptr}};
  }
  for (const ScheduleRow& s : run.schedule) {
    derived["schedule"][s.kernel] = {
        {"invocations", s.invocations},
        {"offloaded", s.offloaded},
        {"offloaded_fraction", s.invocations > 0 ? double(s.offloaded) / double(s.invocations) : 0},
        {"always_vs_policy", std::isfinite(s.always_s) && s.policy_s > 0
                                 ? finite_or_null(s.always_s / s.policy_s - 1)
                                 : nullptr},
        {"r_squared_train", finite_or_null(s.r_squared_train)},
        {"r_squared_eval", finite_or_null(s.r_squared_eval)},
        {"gap_to_oracle", finite_or_null(s.gap_to_oracle)}};
  }
  for (const BackendBreakdown& b : backend_breakdown(run)) {
    nlohmann::json parts = nlohmann::json::object();
    for (const auto& [name, ms] : b.parts) parts[name] = ms;
    derived["backend"][b.mode][b.variant] = parts;
  }
  return {{"system", run.summary}, {"derived", derived}};
}

std::optional<std::string> metric_mode(const std::string& path) {
  const std::vector<std::string> keys = path_keys(path);
  const auto key = [&keys](std::size_t i) { return i < keys.size() ? keys[i] : std::string(); };
  std::string mode;
  if (key(0) == "system" && key(1) == "comparison") {
    mode = key(2);
  } else if (key(0) == "system" && key(2) == "modes") {
    mode = key(3);
  } else if (key(0) == "derived" && key(1) == "backend") {
    mode = key(2);
  } else if (key(0) == "derived" && (key(1) == "kernels" || key(1) == "schedule")) {
    if (const arch::AccelerableKernel* k = arch::find_accelerable_kernel(key(2))) {
      mode = std::string(k->mode);
    }
  }
  if (mode.empty() || mode == "all") return std::nullopt;
  return mode;
}

std::optional<std::set<std::string>> modes_with_frames(const nlohmann::json& metrics) {
  const nlohmann::json::json_pointer pointer("/system/baseline/modes");
  if (!metrics.contains(pointer) || !metrics.at(pointer).is_object()) return std::nullopt;
  std::set<std::string> modes;
  for (const auto& [mode, summary] : metrics.at(pointer).items()) {
    if (mode == "all") continue;
    if (summary.is_object() && summary.contains("frames") && summary["frames"].is_number() &&
        summary["frames"].get<double>() == 0) {
      continue;
    }
    modes.insert(mode);
  }
  return modes;
}

std::optional<double> metric_at(const nlohmann::json& tree, const std::string& path) {
  const nlohmann::json* node = &tree;
  for (const std::string& key : path_keys(path)) {
    if (!node->is_object() || !node->contains(key)) return std::nullopt;
    node = &(*node)[key];
  }
  if (!node->is_number()) return std::nullopt;
  return node->get<double>();
}

std::vector<std::pair<std::string, double>> numeric_figures(const nlohmann::json& tree) {
  std::vector<std::pair<std::string, double>> out;
  const auto walk = [&out](const auto& self, const nlohmann::json& node,
                           const std::string& path) -> void {
    if (node.is_number()) {
      out.emplace_back(path, node.get<double>());
    } else if (node.is_object()) {
      for (const auto& [key, value] : node.items()) {
        self(self, value, path.empty() ? key : path + "." + key);
      }
    }
  };
  walk(walk, tree, "");
  return out;
}

std::vector<std::pair<std::string, Interval>> figures_over_runs(
    const std::vector<nlohmann::json>& trees) {
  std::vector<std::pair<std::string, Interval>> out;
  if (trees.empty()) return out;
  for (const auto& [path, first] : numeric_figures(trees.front())) {
    std::vector<double> samples = {first};
    for (std::size_t t = 1; t < trees.size(); ++t) {
      const std::optional<double> v = metric_at(trees[t], path);
      if (!v) break;
      samples.push_back(*v);
    }
    if (samples.size() != trees.size()) continue;  // not every run has it
    bool finite = true;
    for (double v : samples) finite = finite && std::isfinite(v);
    if (!finite) continue;
    out.emplace_back(path, student_t_interval(samples, path));
  }
  return out;
}

bool is_headline_figure(const std::string& path) {
  const std::vector<std::string> parts = [&] {
    std::vector<std::string> p;
    std::size_t begin = 0;
    for (std::size_t dot = path.find('.'); dot != std::string::npos; dot = path.find('.', begin)) {
      p.push_back(path.substr(begin, dot - begin));
      begin = dot + 1;
    }
    p.push_back(path.substr(begin));
    return p;
  }();
  if (parts.size() < 3 || parts[0] != "system") return false;
  if (parts[1] == "comparison") return parts.size() == 4 && parts[3] == "e2e_speedup";
  if (parts[1] != "baseline" && parts[1] != "accelerated") return false;
  if (parts.size() == 3) {
    return parts[2] == "fps_without_pipelining" || parts[2] == "fps_with_pipelining";
  }
  return parts.size() == 6 && parts[2] == "modes" && parts[5] == "mean" &&
         (parts[4] == "e2e_ms" || parts[4] == "energy_j");
}

std::string format_figures_over_runs(const std::vector<std::pair<std::string, Interval>>& figures,
                                     bool headline_only) {
  std::string text = fmt::format("{:<52} {:>12}  {:<27} {:>3}\n", "figure", "mean",
                                 "95 % interval (Student t)", "n");
  for (const auto& [path, i] : figures) {
    if (headline_only && !is_headline_figure(path)) continue;
    text += fmt::format("{:<52} {:>12.4g}  [{:>11.4g}, {:>11.4g}] {:>3}\n", path, i.mean, i.low,
                        i.high, i.n);
  }
  return text;
}

}  // namespace edx::reports
