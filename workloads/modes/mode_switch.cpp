#include "workloads/modes/mode_switch.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace edx::modes {

void ModeSwitchOptions::validate() const {
  auto require = [](bool ok, const char* field, const char* expected) {
    if (!ok) throw std::runtime_error(fmt::format("mode switch {}: expected {}", field, expected));
  };
  require(gps_window_s > 0, "gps_window_s", "a time > 0 s");
  require(gps_min_fixes >= 1, "gps_min_fixes", "an integer >= 1");
  require(gps_max_sigma_m > 0, "gps_max_sigma_m", "a distance > 0 m");
  require(map_probe_frames >= 1, "map_probe_frames", "an integer >= 1");
  require(registration_failures_to_fall_back >= 1, "registration_failures_to_fall_back",
          "an integer >= 1");
}

std::string ModeSwitchOptions::to_string() const {
  return fmt::format(
      "GPS usable with >= {} fixes of sigma <= {} m in the last {} s; a map is tried for {} "
      "frames and dropped after {} failed frames in a row",
      gps_min_fixes, gps_max_sigma_m, gps_window_s, map_probe_frames,
      registration_failures_to_fall_back);
}

const char* to_string(MapUse use) {
  switch (use) {
    case MapUse::kNone:
      return "none";
    case MapUse::kProbing:
      return "probing";
    case MapUse::kUsable:
      return "usable";
    case MapUse::kUnusable:
      return "unusable";
  }
  return "?";
}

trace::BackendMode choose_mode(bool gps_is_usable, MapUse map) {
  if (gps_is_usable) return trace::BackendMode::Vio;
  if (map == MapUse::kProbing || map == MapUse::kUsable) return trace::BackendMode::Registration;
  return trace::BackendMode::Slam;
}

bool gps_usable(std::span<const datasets::GpsFix> fixes, std::int64_t t_ns,
                const ModeSwitchOptions& options) {
  const auto window_ns = static_cast<std::int64_t>(options.gps_window_s * 1e9);
  // Fixes in (t - window, t]: the first after t - window up to the last at or before t.
  const auto after = [](const datasets::GpsFix& f, std::int64_t t) { return f.t_ns <= t; };
  const auto first =
      std::partition_point(fixes.begin(), fixes.end(),
                           [&](const datasets::GpsFix& f) { return after(f, t_ns - window_ns); });
  const auto last = std::partition_point(first, fixes.end(),
                                         [&](const datasets::GpsFix& f) { return after(f, t_ns); });
  const auto good = std::count_if(
      first, last, [&](const datasets::GpsFix& f) { return f.sigma_m <= options.gps_max_sigma_m; });
  return good >= options.gps_min_fixes;
}

ModeSwitch::ModeSwitch(ModeSwitchOptions options, bool map_is_loaded)
    : options_(options), map_(map_is_loaded ? MapUse::kProbing : MapUse::kNone) {
  options_.validate();
}

ModeDecision ModeSwitch::decide(std::int64_t t_ns, std::span<const datasets::GpsFix> fixes) {
  ModeDecision d;
  d.gps_usable = gps_usable(fixes, t_ns, options_);
  d.map = map_;
  d.mode = choose_mode(d.gps_usable, map_);
  return d;
}

void ModeSwitch::report_registration(bool registered) {
  if (map_ != MapUse::kProbing && map_ != MapUse::kUsable) return;
  if (registered) {
    map_ = MapUse::kUsable;
    failures_in_a_row_ = 0;
    return;
  }
  ++failures_in_a_row_;
  const int limit = map_ == MapUse::kProbing ? options_.map_probe_frames
                                             : options_.registration_failures_to_fall_back;
  if (failures_in_a_row_ >= limit) {
    map_ = MapUse::kUnusable;
    failures_in_a_row_ = 0;
  }
}

void ModeSwitch::map_loaded() {
  map_ = MapUse::kProbing;
  failures_in_a_row_ = 0;
}

}  // namespace edx::modes
