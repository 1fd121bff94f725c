#pragma once
// `edx gen`: renders a synthetic dataset of one of the four scenarios in the EuRoC layout.
//
// Output layout under DIR:
//   unknown scenarios:  DIR/mav0/...                       one traversal
//   known scenarios:    DIR/map/mav0/...  DIR/loc/mav0/...  a mapping run, and a localization
//                       run one hour later through the same world: by default re-traversing
//                       the mapping route (offset sideways, slower), or diverging from it
//   always:             DIR/edx_gen.yaml                   what was generated, with which options
// Outdoor scenarios add mav0/gps0; indoor ones have no GPS. Everything is written into a
// temporary sibling folder first and renamed to DIR at the end.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/datasets/synthetic/inertial.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/stereo_camera.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"

namespace edx::synthetic {

enum class Scenario { kIndoorUnknown, kIndoorKnown, kOutdoorUnknown, kOutdoorKnown };

/// Parses indoor_unknown | indoor_known | outdoor_unknown | outdoor_known.
Scenario parse_scenario(std::string_view text);
std::string_view to_string(Scenario scenario);
bool is_outdoor(Scenario scenario);
bool has_map_run(Scenario scenario);

inline constexpr double kCameraRateHz = 20.0;
inline constexpr std::int64_t kCameraPeriodNs = 50'000'000;
/// First time stamp of a dataset (2020-09-13 12:26:40 UTC); the localization run starts an hour
/// after the mapping run.
inline constexpr std::int64_t kStartTimeNs = 1'600'000'000'000'000'000;
inline constexpr std::int64_t kLocalizationDelayNs = 3'600'000'000'000;

struct GenerateOptions {
  Scenario scenario = Scenario::kIndoorUnknown;
  int frames = 200;  ///< stereo frames per run
  /// Known scenarios: stereo frames of the map run (default: `frames`). A longer map run maps
  /// more of the world than the loc run (which re-traverses its route from the start) visits:
  /// the map-size option of the registration studies (docs/REGISTRATION.md).
  std::optional<int> map_frames;
  /// Renders and writes only frames 0, n, 2n, ... of each run (n = frame_stride), with the
  /// images and time stamps those frames have in the full run (camera rate 20/n Hz); IMU, ground
  /// truth and GPS stay complete. For data of which only every n-th frame is read (the
  /// vocabulary training of `edx trace --mix`).
  int frame_stride = 1;
  std::optional<Resolution> resolution;  ///< default: the rig's native resolution
  std::optional<RigKind> rig;            ///< default: by resolution, else by scenario
  std::uint64_t seed = 1;
  std::filesystem::path out;
  bool force = false;  ///< replace an existing non-empty DIR
  int threads = 2;
  ImuModel imu;
  GpsModel gps;
  ImageSensorOptions image;
  /// Known scenarios: how the loc run relates to the map run's route (trajectory.hpp). The
  /// default re-traverses it, so a map built on the map run covers the loc run.
  RevisitMode loc_route = RevisitMode::kRetraverse;
  double loc_lateral_offset_m = 0.3;  ///< kRetraverse: sideways offset from the map lane
  double loc_speed_scale = 0.85;      ///< kRetraverse: speed factor against the map run's draw
};

/// Parses retraverse | diverge.
RevisitMode parse_loc_route(std::string_view text);
std::string_view to_string(RevisitMode mode);

/// The world of a scenario for a dataset seed (warehouse indoors, street outdoors); the same
/// call as the generator makes, so tests can compare images with the world they show.
Scene build_scene(Scenario scenario, std::uint64_t seed);

/// The rig the options resolve to: --rig if given; else the rig whose native resolution is
/// --resolution; else euroc indoors and car outdoors. Resolution defaults to the rig's native.
StereoRig resolve_rig(const GenerateOptions& options);

/// Progress: run name ("map", "loc" or "" for single-run scenarios), frames done, frames total.
using ProgressFn = std::function<void(std::string_view run, int done, int total)>;

struct RunSummary {
  std::string name;            ///< "", "map" or "loc"
  std::filesystem::path mav0;  ///< final location
  int frames = 0;              ///< frames written (every frame_stride-th of the run)
  std::size_t imu_samples = 0;
  std::size_t gps_fixes = 0;
  double duration_s = 0;
  double path_length_m = 0;
  double mean_speed_m_s = 0;
  std::vector<int> route;
};

struct GenerateSummary {
  StereoRig rig;
  std::vector<RunSummary> runs;
  double render_seconds = 0;  ///< wall time spent rendering and exposing images
  double total_seconds = 0;
};

/// Generates the dataset; throws std::runtime_error on bad options (frames < 1, existing
/// non-empty output without force, ...) or I/O failure, leaving no partial output behind.
GenerateSummary generate_dataset(const GenerateOptions& options, const ProgressFn& progress = {});

}  // namespace edx::synthetic
