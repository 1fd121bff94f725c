#include "sim_core/timeline.hpp"

#include <algorithm>
#include <stdexcept>

#include "common/atomic_file.hpp"

namespace edx::sim {

Timeline::TrackId Timeline::track(const std::string& group, const std::string& name) {
  const auto key = std::make_pair(group, name);
  if (const auto found = track_index_.find(key); found != track_index_.end()) {
    return found->second;
  }
  auto group_it = std::find(groups_.begin(), groups_.end(), group);
  if (group_it == groups_.end()) group_it = groups_.insert(groups_.end(), group);
  const TrackId id = tracks_.size();
  tracks_.push_back(Track{static_cast<std::size_t>(group_it - groups_.begin()), name});
  track_index_.emplace(key, id);
  return id;
}

void Timeline::span(TrackId track, std::string name, Time begin, Time end, nlohmann::json args) {
  if (!enabled_) return;
  if (track >= tracks_.size()) {
    throw std::invalid_argument("edx::sim::Timeline::span '" + name + "': unknown track " +
                                std::to_string(track));
  }
  if (end < begin) {
    throw std::invalid_argument("edx::sim::Timeline::span '" + name + "': ends (" +
                                std::to_string(end) + " ps) before it begins (" +
                                std::to_string(begin) + " ps)");
  }
  if (!args.is_null() && !args.is_object()) {
    throw std::invalid_argument("edx::sim::Timeline::span '" + name +
                                "': args must be a JSON object");
  }
  spans_.push_back(Span{track, std::move(name), begin, end, std::move(args)});
}

void Timeline::retain(Time begin, Time end) {
  std::erase_if(spans_, [&](const Span& s) { return s.end < begin || s.begin > end; });
}

nlohmann::json Timeline::to_json() const {
  nlohmann::json events = nlohmann::json::array();
  // pid = group index + 1, tid = track index + 1 (0 is avoided: some viewers treat it specially).
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    events.push_back({{"ph", "M"},
                      {"name", "process_name"},
                      {"pid", g + 1},
                      {"tid", 0},
                      {"args", {{"name", groups_[g]}}}});
  }
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    const nlohmann::json ids = {{"pid", tracks_[t].group + 1}, {"tid", t + 1}};
    events.push_back({{"ph", "M"},
                      {"name", "thread_name"},
                      {"pid", ids["pid"]},
                      {"tid", ids["tid"]},
                      {"args", {{"name", tracks_[t].name}}}});
    events.push_back({{"ph", "M"},
                      {"name", "thread_sort_index"},
                      {"pid", ids["pid"]},
                      {"tid", ids["tid"]},
                      {"args", {{"sort_index", t}}}});
  }
  for (const Span& span : spans_) {
    nlohmann::json event = {{"ph", "X"},
                            {"name", span.name},
                            {"ts", to_us(span.begin)},
                            {"dur", to_us(span.end - span.begin)},
                            {"pid", tracks_[span.track].group + 1},
                            {"tid", span.track + 1}};
    if (!span.args.is_null()) event["args"] = span.args;
    events.push_back(std::move(event));
  }
  return {{"traceEvents", std::move(events)}, {"displayTimeUnit", "ns"}};
}

void Timeline::write(const std::filesystem::path& path) const {
  common::write_file_atomically(path, to_json().dump());
}

}  // namespace edx::sim
