#pragma once
// The paper's taxonomy of operating scenarios (Sec. III, Fig. 3) as a per-frame decision:
//   GPS usable                      -> VIO (+GPS)
//   no GPS, a map that registers    -> registration
//   no GPS, no (usable) map         -> SLAM (whose map is saved for later)
// GPS quality is read from the GPS stream itself; map usefulness from registering frames against
// it: the map is "probing" until a frame registers (usable) or `map_probe_frames` frames in a row
// fail (unusable). A usable map that then fails `registration_failures_to_fall_back` frames in a
// row is dropped the same way (the machine has left the mapped area).
#include <cstdint>
#include <span>
#include <string>

#include "workloads/datasets/dataset.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

struct ModeSwitchOptions {
  /// GPS is usable at t when at least gps_min_fixes fixes with sigma <= gps_max_sigma_m arrived
  /// in (t - gps_window_s, t]. Defaults: a 10 Hz receiver losing up to half its fixes.
  double gps_window_s = 1.0;
  int gps_min_fixes = 5;
  double gps_max_sigma_m = 5.0;
  /// Frames registered against a new map before it is declared unusable.
  int map_probe_frames = 3;
  /// Consecutive registration failures after which a usable map is dropped.
  int registration_failures_to_fall_back = 5;

  void validate() const;  ///< throws std::runtime_error naming the field
  std::string to_string() const;
};

/// Where the map stands for the mode switch.
enum class MapUse { kNone, kProbing, kUsable, kUnusable };
const char* to_string(MapUse use);

struct ModeDecision {
  trace::BackendMode mode = trace::BackendMode::Slam;
  bool gps_usable = false;
  MapUse map = MapUse::kNone;
};

/// The taxonomy alone: the mode for a GPS state and a map state (probing maps are tried).
trace::BackendMode choose_mode(bool gps_usable, MapUse map);

/// Whether the fixes (sorted by time, any that arrived so far) make GPS usable at t_ns.
bool gps_usable(std::span<const datasets::GpsFix> fixes, std::int64_t t_ns,
                const ModeSwitchOptions& options);

/// The per-frame mode switch over a sequence (one world: a new world gets a new ModeSwitch).
class ModeSwitch {
 public:
  /// `map_loaded`: a map of this world exists (given, or saved by an earlier SLAM segment).
  ModeSwitch(ModeSwitchOptions options, bool map_loaded);

  /// The mode for the frame at t_ns, given every GPS fix received up to t_ns.
  ModeDecision decide(std::int64_t t_ns, std::span<const datasets::GpsFix> fixes);
  /// How registration did on the last frame decide() gave it.
  void report_registration(bool registered);
  /// A map became available (a SLAM segment saved one): probe it from the next frame on.
  void map_loaded();

  MapUse map() const { return map_; }
  const ModeSwitchOptions& options() const { return options_; }

 private:
  ModeSwitchOptions options_;
  MapUse map_;
  int failures_in_a_row_ = 0;
};

}  // namespace edx::modes
