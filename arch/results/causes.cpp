#include "arch/results/causes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace edx::results {

std::string_view cause_resource(std::string_view cause) {
  const std::size_t dot = cause.rfind('.');
  return dot == std::string_view::npos ? cause : cause.substr(0, dot);
}

nlohmann::json CauseSummary::to_json() const {
  const auto shares = [](const std::vector<CauseShare>& list) {
    nlohmann::json j = nlohmann::json::array();
    for (const CauseShare& c : list) {
      j.push_back({{"name", c.name}, {"mean_ms", c.mean_ms}, {"share", c.share}});
    }
    return j;
  };
  return {{"frames", frames},
          {"latency_ms", latency_ms},
          {"bottleneck", bottleneck()},
          {"causes", shares(causes)},
          {"resources", shares(resources)}};
}

namespace {

/// Σ over `frames` (indices into the table) of each cause, as means and shares.
CauseSummary summarize(const CauseTable& t, const std::string& mode,
                       const std::vector<std::size_t>& frames) {
  CauseSummary s;
  s.mode = mode;
  s.frames = frames.size();
  if (frames.empty()) return s;
  const double n = static_cast<double>(frames.size());
  std::vector<double> sum(t.causes.size(), 0.0);
  double latency = 0;
  for (std::size_t f : frames) {
    latency += t.frames[f].latency_ms;
    for (std::size_t c = 0; c < t.causes.size(); ++c) sum[c] += t.at(f, c);
  }
  s.latency_ms = latency / n;
  std::map<std::string, double, std::less<>> by_resource;
  for (std::size_t c = 0; c < t.causes.size(); ++c) {
    if (!(sum[c] > 0)) continue;
    s.causes.push_back({t.causes[c], sum[c] / n, 0});
    by_resource[std::string(cause_resource(t.causes[c]))] += sum[c] / n;
  }
  for (const auto& [name, mean] : by_resource) s.resources.push_back({name, mean, 0});
  for (auto* list : {&s.causes, &s.resources}) {
    for (CauseShare& c : *list) c.share = s.latency_ms > 0 ? c.mean_ms / s.latency_ms : 0.0;
    // Largest first; equal means by name (deterministic).
    std::sort(list->begin(), list->end(), [](const CauseShare& a, const CauseShare& b) {
      return a.mean_ms != b.mean_ms ? a.mean_ms > b.mean_ms : a.name < b.name;
    });
  }
  return s;
}

}  // namespace

std::vector<CauseSummary> summarize_causes(const CauseTable& table) {
  std::map<std::string, std::vector<std::size_t>> by_mode;
  std::vector<std::size_t> all;
  for (std::size_t f = 0; f < table.frames.size(); ++f) {
    if (table.frames[f].dropped) continue;
    by_mode[table.frames[f].mode].push_back(f);
    all.push_back(f);
  }
  std::vector<CauseSummary> out;
  for (const auto& [mode, frames] : by_mode) out.push_back(summarize(table, mode, frames));
  out.push_back(summarize(table, "all", all));
  return out;
}

nlohmann::json causes_json(const CauseTable& table) {
  nlohmann::json j = nlohmann::json::object();
  for (const CauseSummary& s : summarize_causes(table)) j[s.mode] = s.to_json();
  return j;
}

std::vector<FrameCausesRow> frame_causes_rows(const std::string& run_id, const std::string& variant,
                                              const std::string& run, const CauseTable& table) {
  std::vector<FrameCausesRow> rows;
  rows.reserve(table.frames.size());
  for (std::size_t f = 0; f < table.frames.size(); ++f) {
    const CauseTable::Frame& frame = table.frames[f];
    nlohmann::json causes = nlohmann::json::object();
    for (std::size_t c = 0; c < table.causes.size(); ++c) {
      if (table.at(f, c) != 0) causes[table.causes[c]] = table.at(f, c);
    }
    rows.push_back({run_id, variant, run, frame.frame_id, frame.dropped,
                    frame.dropped ? 0.0 : frame.latency_ms, std::move(causes)});
  }
  return rows;
}

CauseTable cause_table_of(const std::vector<FrameCausesRow>& rows,
                          const std::vector<FrameRow>& frames, const std::string& variant,
                          const std::string& run) {
  std::map<std::int64_t, std::string> modes;
  for (const FrameRow& f : frames) {
    if (f.variant == variant) modes[f.frame_id] = f.mode;
  }
  CauseTable t;
  std::map<std::string, std::size_t> column;
  std::vector<std::vector<std::pair<std::size_t, double>>> cells;
  for (const FrameCausesRow& r : rows) {
    if (r.variant != variant || r.run != run) continue;
    const auto mode = modes.find(r.frame_id);
    t.frames.push_back(
        {r.frame_id, mode == modes.end() ? "none" : mode->second, r.dropped, r.latency_ms});
    cells.emplace_back();
    if (!r.causes.is_object()) {
      throw std::runtime_error(
          fmt::format("frame_causes: run {} {} {} frame {}: causes_json is not an object", r.run_id,
                      variant, run, r.frame_id));
    }
    for (const auto& [name, value] : r.causes.items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>())) {
        throw std::runtime_error(
            fmt::format("frame_causes: run {} {} {} frame {}: cause {} is not a finite number",
                        r.run_id, variant, run, r.frame_id, name));
      }
      const auto [it, added] = column.emplace(name, t.causes.size());
      if (added) t.causes.push_back(name);
      cells.back().emplace_back(it->second, value.get<double>());
    }
  }
  t.ms.assign(t.frames.size() * t.causes.size(), 0.0);
  for (std::size_t f = 0; f < cells.size(); ++f) {
    for (const auto& [c, ms] : cells[f]) t.ms[f * t.causes.size() + c] = ms;
  }
  return t;
}

}  // namespace edx::results
