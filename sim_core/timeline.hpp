#pragma once
// Timeline: named spans per track, exported as Chrome trace-event JSON (opens in Perfetto,
// ui.perfetto.dev, and chrome://tracing).
//
// Format: {"traceEvents": [...], "displayTimeUnit": "ns"} where each track is a thread (tid)
// inside a process (pid) named by its group, announced by "M" metadata events
// (process_name / thread_name), and each span is a complete event
// {"ph": "X", "name", "ts", "dur", "pid", "tid", "args"} with ts and dur in microseconds (double:
// ps / 10^6). Spans on one track should nest or follow each other, as viewers expect of a thread.
#include <cstddef>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "sim_core/time.hpp"

namespace edx::sim {

/// Records spans per track when enabled; when disabled every call is a cheap no-op.
class Timeline {
 public:
  /// Index of a track returned by track().
  using TrackId = std::size_t;

  /// A timeline that records (or, with enabled = false, ignores) spans.
  explicit Timeline(bool enabled = true) : enabled_(enabled) {}

  /// True if spans are recorded.
  bool enabled() const noexcept { return enabled_; }
  /// The track `name` in group `group` (a trace "process"), created on first use; the same
  /// (group, name) always returns the same id. Tracks are numbered in creation order.
  TrackId track(const std::string& group, const std::string& name);
  /// A track in the default group "edx".
  TrackId track(const std::string& name) { return track("edx", name); }

  /// Records span `name` on `track` over [begin, end] with optional `args` (a JSON object or
  /// null). Throws std::invalid_argument for an unknown track, end < begin or non-object args.
  void span(TrackId track, std::string name, Time begin, Time end, nlohmann::json args = nullptr);

  /// Drops the spans that do not overlap [begin, end] (keeps a window of a long run); tracks stay.
  void retain(Time begin, Time end);

  /// Number of recorded spans.
  std::size_t span_count() const noexcept { return spans_.size(); }
  /// Number of tracks.
  std::size_t track_count() const noexcept { return tracks_.size(); }

  /// The whole trace as a JSON document (metadata first, then spans in recording order).
  nlohmann::json to_json() const;
  /// Writes to_json() to `path` through a temporary file renamed into place.
  void write(const std::filesystem::path& path) const;

 private:
  struct Track {
    std::size_t group;  ///< index into groups_
    std::string name;
  };
  struct Span {
    TrackId track;
    std::string name;
    Time begin;
    Time end;
    nlohmann::json args;
  };

  bool enabled_;
  std::vector<std::string> groups_;
  std::vector<Track> tracks_;
  std::map<std::pair<std::string, std::string>, TrackId> track_index_;
  std::vector<Span> spans_;
};

}  // namespace edx::sim
