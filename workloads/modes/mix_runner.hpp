#pragma once
// `edx trace --mix NAME`: runs the localization pipeline over a mixed sequence (mix.hpp) and
// writes one trace whose frames record their scenario and the mode the mode switch
// (mode_switch.hpp) chose. Per segment: a fresh frontend (the images jump at a segment boundary)
// and a mode switch for the segment's world; the backend of the chosen mode is created when the
// mode first runs in the segment and kept while it stays; a SLAM segment's map is saved
// (<data>/<world>-map.json) and loaded as the map of later segments in the same world.
// Registration needs a vocabulary: given, or trained once on a separate synthetic world (another
// seed, so that the vocabulary has not seen the mapped warehouse).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/eval/evaluate.hpp"
#include "workloads/frontend/frontend_options.hpp"
#include "workloads/frontend/sample_stats.hpp"
#include "workloads/modes/host_speed_meter.hpp"
#include "workloads/modes/mix.hpp"
#include "workloads/modes/mode_switch.hpp"

namespace edx::modes {

/// A mix's first segment traced once and replayed by later runs of the same segment (the
/// characterization's three runs of a known scenario share their mapping segment): its frames'
/// records (host times included), its summary, its accuracy and its map. An entry is only used
/// for a first segment (nothing traced before it, no map yet: its work depends on nothing else)
/// with the same segment, world, seed, resolution, data folder and options (key in
/// mix_runner.cpp); the replayed rows are the recorded ones, so the trace is as if traced again
/// (apart from host times, which differ between any two traces anyway). Not thread-safe: one
/// cache per sequence of runs.
class SegmentCache;
std::shared_ptr<SegmentCache> make_segment_cache();

struct MixRunOptions {
  MixPlan plan;
  std::filesystem::path data_dir;  ///< generated worlds, saved maps, the trained vocabulary
  std::filesystem::path out;
  bool overwrite = false;
  /// Tasks one after another so that each host time is its own (as in TraceRunOptions).
  frontend::FrontendOptions frontend = [] {
    frontend::FrontendOptions o;
    o.parallel_images = false;
    return o;
  }();
  ModeSwitchOptions mode_switch;
  backend::vio::VioOptions vio;     ///< of the VIO backend (outdoor segments)
  backend::slam::SlamOptions slam;  ///< of the SLAM backend (mapping segments)
  /// The arithmetic of every backend's offloadable kernels (meta precision): run_mix sets the
  /// backends' options' precision to it.
  trace::Precision precision = trace::Precision::kFp64;
  /// Save each SLAM segment's map as <data>/<world>-map.json (later segments use it from
  /// memory either way; sweeps tracing several workloads into one data folder turn this off).
  bool save_maps = true;
  /// Render threads of the world generator (a sweep running several traces at once uses 1).
  int generator_threads = 2;
  /// Vocabulary file for registration; empty: trained into data_dir (vocabulary-s<seed>.bin).
  std::filesystem::path vocabulary;
  /// When the machine-speed reference suite samples (meta host_speed).
  HostSpeedMeterOptions host_speed;
  /// Where the first segment is replayed from when traced before, and recorded to otherwise
  /// (none: always traced).
  std::shared_ptr<SegmentCache> segment_cache;
};

/// Latency and accuracy of the frames one mode ran on.
struct ModeRunSummary {
  std::string mode;
  std::size_t frames = 0;
  std::size_t estimated_frames = 0;
  frontend::SampleStats frontend_ms, backend_ms;
  /// Per kernel: host ms per frame of this mode (0 where it did not run), and its share of the
  /// mode's mean backend time.
  std::vector<std::pair<std::string, frontend::SampleStats>> kernel_ms;
  /// ATE RMSE pooled over the segments (each aligned on its own, position + yaw with the IMU):
  /// sqrt(sum_s pairs_s rmse_s^2 / sum_s pairs_s).
  std::optional<double> ate_rmse_m;
  std::size_t ate_pairs = 0;
};

struct SegmentRunSummary {
  std::string name;
  std::string scenario;
  std::int64_t first_frame_id = 0;  ///< its first frame's id in the trace
  std::size_t frames = 0;
  /// Per mode that ran on it with enough estimates: ATE RMSE on this segment alone (aligned on
  /// its own, position + yaw with the IMU), m, and its pose pairs.
  std::map<std::string, double> ate_rmse_m;
  std::map<std::string, std::size_t> ate_pairs;
  std::map<std::string, std::size_t> frames_by_mode;
  std::size_t registration_failures = 0;
  std::optional<std::filesystem::path> map_saved;
};

struct MixRunSummary {
  std::filesystem::path out;
  std::string plan;  ///< MixPlan::to_string()
  std::size_t frames = 0;
  std::vector<SegmentRunSummary> segments;
  std::vector<ModeRunSummary> modes;  ///< registration, vio, slam (those that ran)
  double wall_seconds = 0;
};

/// Progress: stage ("data", "vocabulary", or the segment name), done, total.
using MixProgress =
    std::function<void(std::string_view stage, std::size_t done, std::size_t total)>;

/// Generates the plan's worlds under data_dir and trains the registration vocabulary when the
/// plan needs one and none is given, reusing what is already there (run_mix calls it first).
/// Not safe to run twice at once on one data_dir: callers sharing a folder serialize it.
void prepare_mix_data(const MixRunOptions& options, const MixProgress& progress = {});

/// Generates the data, runs the segments and writes the trace (all or nothing: the trace file
/// appears only when complete). Throws std::runtime_error naming the file or option on bad input.
MixRunSummary run_mix(const MixRunOptions& options, const MixProgress& progress = {});

nlohmann::json to_json(const MixRunSummary& summary);
std::string format_summary(const MixRunSummary& summary);

}  // namespace edx::modes
