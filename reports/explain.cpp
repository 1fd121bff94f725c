#include "reports/explain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "arch/results/causes.hpp"

namespace edx::reports {

nlohmann::json explain_run(const ResultsData& data, const ExplainRequest& request) {
  const RunData& run = pick_run(data, request.run_id);
  nlohmann::json out = {{"run_id", run.run_id},
                        {"platform", run.platform},
                        {"trace", run.trace},
                        {"attribution", nlohmann::json::object()}};
  for (const char* variant : {"baseline", "accelerated"}) {
    const nlohmann::json::json_pointer where(fmt::format("/{}/attribution", variant));
    if (!run.summary.contains(where) || !run.summary[where].is_object()) {
      throw std::runtime_error(fmt::format(
          "{}: run {} has no critical-path attribution (simulated with --model analytical, or "
          "by an edx before results schema 5); simulate it again",
          data.path.string(), run.run_id));
    }
    out["attribution"][variant] = run.summary[where];
  }
  if (!request.frame) return out;
  const std::int64_t id = *request.frame;
  nlohmann::json frame = {{"frame_id", id}, {"variants", nlohmann::json::object()}};
  for (const results::FrameRow& f : run.frame_rows) {
    if (f.frame_id == id) frame["mode"] = f.mode;
  }
  std::vector<results::FrameCausesRow> rows;  // the frame's, each checked by cause_table_of
  for (const results::FrameCausesRow& r : run.frame_causes) {
    if (r.frame_id == id) rows.push_back(r);
  }
  for (const results::FrameCausesRow& r : rows) {
    results::CauseTable table;
    try {
      table = results::cause_table_of(rows, {}, r.variant, r.run);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("{}: {}", data.path.string(), e.what()));
    }
    nlohmann::json causes = nlohmann::json::object();
    for (std::size_t c = 0; c < table.causes.size(); ++c) causes[table.causes[c]] = table.at(0, c);
    frame["variants"][r.variant][r.run] = {
        {"latency_ms", r.latency_ms}, {"dropped", r.dropped}, {"causes", std::move(causes)}};
  }
  if (frame["variants"].empty()) {
    throw std::runtime_error(
        run.frame_causes.empty()
            ? fmt::format("{}: run {} has no per-frame attribution (frame_causes; a sweep point "
                          "stores it with --per-frame)",
                          data.path.string(), run.run_id)
            : fmt::format("{}: run {} has no frame {} (--frame)", data.path.string(), run.run_id,
                          id));
  }
  out["frame"] = std::move(frame);
  return out;
}

namespace {

const char* run_title(const std::string& run) {
  return run == "isolated" ? "isolated (a frame alone: the paper's latency)"
                           : "streamed (frames at the sensor rate, or back to back; queueing "
                             "included)";
}

/// One variant and run: causes (rows, by the mean over all frames) by mode (columns).
std::string format_run(const std::string& variant, const std::string& run,
                       const nlohmann::json& modes) {
  std::vector<std::string> names;  // modes, "all" last
  for (const auto& [mode, s] : modes.items()) {
    if (mode != "all") names.push_back(mode);
  }
  names.push_back("all");
  if (!modes.contains("all")) return "";
  std::string text = fmt::format("\n{} {}\n  {:<28}", variant, run_title(run), "cause (mean ms)");
  for (const std::string& m : names) text += fmt::format(" {:>18}", m);
  const auto mean_of = [&](const std::string& mode,
                           const std::string& cause) -> const nlohmann::json* {
    for (const nlohmann::json& c : modes[mode]["causes"]) {
      if (c["name"] == cause) return &c;
    }
    return nullptr;
  };
  text += fmt::format("\n  {:<28}", "latency");
  for (const std::string& m : names) {
    text += fmt::format(" {:>18}", fmt::format("{:.3f}", modes[m]["latency_ms"].get<double>()));
  }
  for (const nlohmann::json& c : modes["all"]["causes"]) {
    const std::string cause = c["name"];
    text += fmt::format("\n  {:<28}", cause);
    for (const std::string& m : names) {
      const nlohmann::json* x = mean_of(m, cause);
      text += fmt::format(
          " {:>18}", x == nullptr ? std::string("-")
                                  : fmt::format("{:.3f} ({:.0f} %)", (*x)["mean_ms"].get<double>(),
                                                100 * (*x)["share"].get<double>()));
    }
  }
  text += fmt::format("\n  {:<28}", "bottleneck");
  for (const std::string& m : names) {
    text += fmt::format(" {:>18}", modes[m]["bottleneck"].get<std::string>());
  }
  return text + "\n";
}

}  // namespace

std::string format_explain(const nlohmann::json& e) {
  std::string text =
      fmt::format("run        {}\nplatform   {}\ntrace      {}\n", e["run_id"].get<std::string>(),
                  e["platform"].get<std::string>(), e["trace"].get<std::string>());
  for (const char* variant : {"baseline", "accelerated"}) {
    const nlohmann::json& runs = e["attribution"][variant];
    for (const char* run : {"isolated", "streamed"}) {
      if (runs.contains(run)) text += format_run(variant, run, runs[run]);
    }
  }
  if (e.contains("frame")) {
    const nlohmann::json& f = e["frame"];
    text += fmt::format("\nframe {} ({})\n", f["frame_id"].get<std::int64_t>(),
                        f.value("mode", std::string("mode unknown")));
    for (const char* variant : {"baseline", "accelerated"}) {
      if (!f["variants"].contains(variant)) continue;
      for (const auto& [run, r] : f["variants"][variant].items()) {
        if (r["dropped"].get<bool>()) {
          text += fmt::format("  {} {}: dropped by the camera queue\n", variant, run);
          continue;
        }
        std::vector<std::pair<double, std::string>> causes;
        for (const auto& [name, ms] : r["causes"].items()) causes.emplace_back(ms, name);
        std::sort(causes.rbegin(), causes.rend());
        text += fmt::format("  {} {}: {:.3f} ms =", variant, run, r["latency_ms"].get<double>());
        for (std::size_t i = 0; i < causes.size(); ++i) {
          text +=
              fmt::format("{} {} {:.3f}", i == 0 ? "" : " +", causes[i].second, causes[i].first);
        }
        text += "\n";
      }
    }
  }
  return text;
}

}  // namespace edx::reports
