#include "workloads/modes/mix_runner.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "workloads/backend/registration/bow/training.hpp"
#include "workloads/backend/registration/registration_backend.hpp"
#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/backend/vio/vio_backend.hpp"
#include "workloads/eval/segment_ate.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/modes/pipeline.hpp"
#include "workloads/modes/trace_session.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;
using trace::BackendMode;

constexpr BackendMode kModes[] = {BackendMode::Registration, BackendMode::Vio, BackendMode::Slam};

/// Per-frame series of one mode.
struct ModeSeries {
  std::vector<double> frontend_ms, backend_ms;
  KernelSeries kernel_ms;  // 0 on frames where it did not run
  std::size_t estimated = 0;
  eval::PooledAte ate;  // over the segments (eval/segment_ate.hpp)
};

/// Estimated and true poses of one (segment, mode), evaluated once the segment ends.
struct PosePairs {
  eval::Trajectory truth, estimate;
};

/// What a traced first segment left: everything a replay adds to the trace and the run.
struct RecordedSegment {
  std::vector<trace::FrameTrace> records;  ///< as appended (frame ids from 0)
  SegmentRunSummary summary;
  std::map<BackendMode, eval::EvalResult> accuracy;  ///< per mode, added to its pooled ATE
  std::string world;                                 ///< world_key of its map
  std::shared_ptr<const backend::slam::Map> map;     ///< its SLAM map (none: no SLAM ran)
};

}  // namespace

class SegmentCache {
 public:
  std::map<std::string, RecordedSegment> entries;  ///< by segment_cache_key
};

std::shared_ptr<SegmentCache> make_segment_cache() { return std::make_shared<SegmentCache>(); }

namespace {

std::shared_ptr<const bow::Vocabulary> load_or_train_vocabulary(const MixRunOptions& options,
                                                                const MixProgress& progress) {
  if (!options.vocabulary.empty()) {
    return std::make_shared<const bow::Vocabulary>(bow::Vocabulary::load(options.vocabulary));
  }
  const MixPlan& plan = options.plan;
  // A separate world (seed + 1) that none of the segments shows.
  const std::uint64_t seed = plan.seed + 1;
  const fs::path file =
      options.data_dir /
      fmt::format("vocabulary-{}x{}-s{}.bin", plan.resolution.width, plan.resolution.height, seed);
  if (fs::exists(file)) return std::make_shared<const bow::Vocabulary>(bow::Vocabulary::load(file));
  // The training samples frames 0, 4, ..., 96 of a 100-frame run: only those are rendered and
  // written (frame_stride; the same images as in the full run, so the same vocabulary), and the
  // training reads each frame of that folder. The folder's name says so: a full 100-frame world
  // of an older run ("vocabulary-world-...") is not mistaken for it.
  constexpr int kTrainingStride = 4;
  synthetic::GenerateOptions world;
  world.scenario = synthetic::Scenario::kIndoorUnknown;
  world.frames = 100;
  world.frame_stride = kTrainingStride;
  world.resolution = plan.resolution;
  world.seed = seed;
  world.threads = options.generator_threads;
  world.out =
      options.data_dir / fmt::format("vocabulary-world-{}x{}-s{}-every{}", plan.resolution.width,
                                     plan.resolution.height, seed, kTrainingStride);
  if (!fs::exists(world.out / "edx_gen.yaml")) {
    synthetic::generate_dataset(world, [&](std::string_view, int done, int total) {
      if (progress) progress("vocabulary data", done, total);
    });
  }
  bow::TrainingOptions training;
  training.datasets = {{world.out, datasets::DatasetFormat::kEuroc, {}}};
  training.frame_stride = 1;
  training.vocabulary.depth = 4;  // 10^4 words for a few thousand training descriptors
  training.vocabulary.seed = seed;
  bow::TrainedVocabulary trained =
      bow::train_vocabulary(training, [&](std::string_view, std::size_t done, std::size_t total) {
        if (progress) progress("vocabulary", done, total);
      });
  trained.vocabulary.save(file);
  return std::make_shared<const bow::Vocabulary>(std::move(trained.vocabulary));
}

/// Whether a later segment revisits a world (it then registers against that world's map).
bool needs_registration(const MixPlan& plan) {
  return std::any_of(plan.segments.begin(), plan.segments.end(), [&](const MixSegment& s) {
    return std::count_if(plan.segments.begin(), plan.segments.end(),
                         [&](const MixSegment& o) { return o.world == s.world; }) > 1;
  });
}

std::string world_key(const MixPlan& plan, const MixSegment& segment) {
  return fmt::format("{}-{}x{}-s{}", segment.world, plan.resolution.width, plan.resolution.height,
                     plan.seed);
}

/// Everything a first segment's work depends on: the segment, its world's seed and resolution,
/// the data folder (its images, where its map is saved) and the options of the frontend, the
/// mode switch, the backends and the vocabulary. Equal keys trace the same rows of work.
std::string segment_cache_key(const MixRunOptions& options, const MixSegment& segment) {
  return fmt::format(
      "{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", world_key(options.plan, segment),
      segment.name, trace::to_string(segment.scenario),
      synthetic::to_string(segment.world_scenario), segment.run, segment.frames,
      segment.mode ? trace::to_string(*segment.mode) : "switch", options.data_dir.string(),
      options.save_maps, frontend::to_json(options.frontend).dump(),
      options.mode_switch.to_string(), options.vio.to_json().dump(), options.slam.to_json().dump(),
      trace::to_string(options.precision), options.vocabulary.string());
}

/// The datasets of the plan's segments, in order.
std::vector<std::unique_ptr<datasets::Dataset>> open_segments(const MixRunOptions& options) {
  std::vector<std::unique_ptr<datasets::Dataset>> datasets;
  for (const MixSegment& s : options.plan.segments) {
    const fs::path mav0 = segment_mav0(options.plan, s, options.data_dir);
    datasets.push_back(datasets::open_dataset(mav0.parent_path(), datasets::DatasetFormat::kEuroc));
  }
  return datasets;
}

/// The registration backend's options at the workload's precision.
backend::registration::RegistrationOptions registration_options(trace::Precision precision) {
  backend::registration::RegistrationOptions options;
  options.precision = precision;
  return options;
}

/// The mixed trace's meta: every segment's camera and data, the options of the mode switch and
/// of the backends, the precision.
TraceRunMeta mix_meta(const MixRunOptions& options,
                      const std::vector<std::unique_ptr<datasets::Dataset>>& datasets) {
  const MixPlan& plan = options.plan;
  nlohmann::json cameras = nlohmann::json::array();
  nlohmann::json segments = nlohmann::json::array();
  for (std::size_t si = 0; si < plan.segments.size(); ++si) {
    const MixSegment& s = plan.segments[si];
    const datasets::StereoCalibration& calibration = datasets[si]->calibration();
    const datasets::CameraIntrinsics& k = calibration.rectified;
    cameras.push_back(
        fmt::format("{}: pinhole-rectified fx={:.4f} fy={:.4f} cx={:.4f} cy={:.4f} b={:.6f}m",
                    s.name, k.fx, k.fy, k.cx, k.cy, calibration.baseline_m));
    segments.push_back({{"name", s.name},
                        {"scenario", trace::to_string(s.scenario)},
                        {"frames", s.frames},
                        {"data", segment_mav0(plan, s, options.data_dir).string()}});
  }
  TraceRunMeta meta;
  meta.dataset = fmt::format("synthetic mix {}", plan.name);
  meta.sequence = fmt::format("mix:{}", plan.name);
  meta.resolution = fmt::format("{}x{}", plan.resolution.width, plan.resolution.height);
  meta.camera_model = cameras.dump();
  meta.pipeline_params = {
      {"backend_mode", "mixed"},      {"mix", plan.name},
      {"segments", segments},         {"mode_switch", options.mode_switch.to_string()},
      {"vio", options.vio.to_json()}, {"slam", options.slam.to_json()}};
  meta.frames = static_cast<std::size_t>(plan.total_frames());
  meta.precision = options.precision;
  return meta;
}

/// The mixed run's segments one after another into one trace, and the per-mode series they
/// add to.
class MixRun {
 public:
  MixRun(const MixRunOptions& options, std::shared_ptr<const bow::Vocabulary> vocabulary,
         TraceSession& session, const MixProgress& progress)
      : options_(options),
        vocabulary_(std::move(vocabulary)),
        session_(session),
        progress_(progress) {}

  /// Traces the segment's frames with a fresh frontend and mode switch, then measures each
  /// mode's accuracy on it and keeps (and saves) its SLAM map for the world.
  /// A first segment recorded in options.segment_cache is replayed instead; a first segment
  /// not yet there is recorded into it.
  SegmentRunSummary run_segment(const MixSegment& segment, const datasets::Dataset& dataset);
  std::size_t frames() const { return static_cast<std::size_t>(frame_id_); }
  /// Latency and accuracy per mode that ran (registration, vio, slam).
  std::vector<ModeRunSummary> mode_summaries() const;

 private:
  /// What one segment's frames share: a fresh frontend (the images jump at a segment boundary),
  /// a mode switch for its world and the backends it chose.
  struct Segment {
    /// `maps`: the worlds' maps so far (the mode switch probes this world's map when there is one).
    Segment(const MixSegment& spec, const datasets::Dataset& dataset, const MixRunOptions& options,
            const std::map<std::string, std::shared_ptr<const backend::slam::Map>>& maps)
        : spec(spec),
          dataset(dataset),
          world(world_key(options.plan, spec)),
          sequence(fmt::format("synthetic:{}:{}", world, spec.run.empty() ? "run" : spec.run)),
          frontend(options.frontend,
                   {dataset.calibration().rectified.fx, dataset.calibration().baseline_m}),
          mode_switch(options.mode_switch, maps.count(world) > 0) {
      summary.name = spec.name;
      summary.scenario = trace::to_string(spec.scenario);
    }

    const MixSegment& spec;  ///< the plan's segment
    const datasets::Dataset& dataset;
    std::string world;     ///< world_key: its map's key
    std::string sequence;  ///< the frames' sequence
    frontend::StereoFrontend frontend;
    ModeSwitch mode_switch;
    std::map<BackendMode, std::unique_ptr<backend::Backend>> backends;  ///< made on first use
    std::map<BackendMode, PosePairs> poses;  ///< of the frames with an estimate and ground truth
    std::map<BackendMode, eval::EvalResult> accuracy;  ///< per mode with enough estimates
    SegmentRunSummary summary;
    std::int64_t previous_t_ns = std::numeric_limits<std::int64_t>::min();
  };

  /// The backend of `mode` for the segment (registration against its world's map).
  std::unique_ptr<backend::Backend> make_backend(BackendMode mode, const Segment& segment) const;
  /// Frame i of the segment through the frontend, the mode switch and the chosen backend, into
  /// the trace and the mode's series.
  trace::FrameTrace trace_frame(Segment& segment, std::size_t i);
  /// A traced frame's host times, kernels and estimate into its mode's series.
  void add_to_series(const trace::FrameTrace& record);
  /// A recorded first segment into the trace, the series and the maps, as run_segment would.
  SegmentRunSummary replay(const RecordedSegment& recorded, const MixSegment& segment);
  /// Each mode's ATE on the segment (aligned on its own) into its pooled squared error.
  void add_accuracy(Segment& segment);
  /// The segment's SLAM map, for later segments in its world (saved when save_maps).
  void keep_map(Segment& segment);

  const MixRunOptions& options_;
  std::shared_ptr<const bow::Vocabulary> vocabulary_;
  TraceSession& session_;
  const MixProgress& progress_;
  std::map<BackendMode, ModeSeries> series_;
  std::map<std::string, std::shared_ptr<const backend::slam::Map>> maps_;  // by world
  std::int64_t frame_id_ = 0;
};

SegmentRunSummary MixRun::run_segment(const MixSegment& segment, const datasets::Dataset& dataset) {
  // A first segment's work depends on nothing traced before it (fresh frontend, mode switch and
  // backends; no map of any world yet): its key says all it depends on.
  SegmentCache* cache =
      frame_id_ == 0 && maps_.empty() && series_.empty() ? options_.segment_cache.get() : nullptr;
  const std::string key = cache ? segment_cache_key(options_, segment) : std::string();
  if (cache) {
    if (const auto it = cache->entries.find(key); it != cache->entries.end()) {
      return replay(it->second, segment);
    }
  }
  Segment s(segment, dataset, options_, maps_);
  s.summary.first_frame_id = frame_id_;
  const std::size_t frames =
      std::min<std::size_t>(dataset.frame_count(), static_cast<std::size_t>(segment.frames));
  RecordedSegment recorded;
  for (std::size_t i = 0; i < frames; ++i) {
    trace::FrameTrace record = trace_frame(s, i);
    if (cache) recorded.records.push_back(std::move(record));
    if (progress_) progress_(segment.name, i + 1, frames);
  }
  s.summary.frames = frames;
  add_accuracy(s);
  keep_map(s);
  if (cache) {  // only a whole segment is kept
    recorded.summary = s.summary;
    recorded.accuracy = s.accuracy;
    recorded.world = s.world;
    if (const auto it = maps_.find(s.world); it != maps_.end()) recorded.map = it->second;
    cache->entries.emplace(key, std::move(recorded));
  }
  return std::move(s.summary);
}

SegmentRunSummary MixRun::replay(const RecordedSegment& recorded, const MixSegment& segment) {
  const std::size_t frames = recorded.records.size();
  for (std::size_t i = 0; i < frames; ++i) {
    session_.append(recorded.records[i]);
    add_to_series(recorded.records[i]);
    ++frame_id_;
    if (progress_) progress_(segment.name, i + 1, frames);
  }
  for (const auto& [mode, result] : recorded.accuracy) series_[mode].ate.add(result);
  if (recorded.map) {
    // Saved again, as the traced segment would: a later segment of the same world (a SLAM
    // measured run) may have saved its own map to the same file since.
    const std::optional<fs::path>& file = recorded.summary.map_saved;
    if (file) backend::slam::save_map(*recorded.map, *file);
    maps_[recorded.world] = recorded.map;
  }
  return recorded.summary;
}

std::unique_ptr<backend::Backend> MixRun::make_backend(BackendMode mode, const Segment& s) const {
  switch (mode) {
    case BackendMode::Vio:
      return backend::vio::make_vio_backend(s.dataset, options_.vio);
    case BackendMode::Slam:
      return backend::slam::make_slam_backend(s.dataset, options_.slam);
    case BackendMode::Registration:
      return backend::registration::make_registration_backend(
          s.dataset, registration_options(options_.precision), maps_.at(s.world), vocabulary_);
    case BackendMode::None:
      break;
  }
  return nullptr;
}

trace::FrameTrace MixRun::trace_frame(Segment& s, std::size_t i) {
  const datasets::Dataset& dataset = s.dataset;
  const datasets::StereoFrame images = dataset.load_frame(i);
  frontend::FrontendFrame result = s.frontend.process(images.left, images.right);
  ModeDecision decision = s.mode_switch.decide(
      images.t_ns, between(dataset.gps(), std::numeric_limits<std::int64_t>::min(), images.t_ns));
  if (s.spec.mode) decision.mode = *s.spec.mode;  // a fixed-algorithm segment
  std::unique_ptr<backend::Backend>& backend = s.backends[decision.mode];
  if (!backend) backend = make_backend(decision.mode, s);

  trace::FrameTrace record;
  record.frame.frame_id = frame_id_++;
  record.frame.timestamp_ns = images.t_ns;
  record.frame.sequence = s.sequence;
  record.frame.scenario = s.spec.scenario;
  record.frame.mode = decision.mode;
  record.frame.gps_available = gps_near(dataset.gps(), images.t_ns);
  record.frame.map_available = decision.map != MapUse::kNone;
  record.frame.frontend_host_ns = result.host_ns;
  record.tasks = result.tasks;
  const std::optional<Eigen::Isometry3d> truth = ground_truth_at(dataset, images.t_ns);
  if (truth) record.frame.ground_truth_pose = to_pose_array(*truth);

  backend::BackendOutput output =
      run_backend_on_frame(*backend, dataset, images, result, s.previous_t_ns, record.frame);
  if (decision.mode == BackendMode::Registration) {
    s.mode_switch.report_registration(output.T_world_body.has_value());
    if (!output.T_world_body) ++s.summary.registration_failures;
  }

  if (output.T_world_body) {
    record.frame.estimated_pose = to_pose_array(*output.T_world_body);
    if (truth) {
      PosePairs& p = s.poses[decision.mode];
      p.truth.poses.push_back(stamped(images.t_ns, record.frame.frame_id, *truth));
      p.estimate.poses.push_back(stamped(images.t_ns, record.frame.frame_id, *output.T_world_body));
    }
  }
  record.kernels = std::move(output.kernels);
  session_.append(record);
  add_to_series(record);
  ++s.summary.frames_by_mode[trace::to_string(decision.mode)];
  s.previous_t_ns = images.t_ns;
  return record;
}

void MixRun::add_to_series(const trace::FrameTrace& record) {
  ModeSeries& series = series_[record.frame.mode];
  add_kernel_times(series.kernel_ms, series.backend_ms.size(), record.kernels);
  series.frontend_ms.push_back(static_cast<double>(record.frame.frontend_host_ns) * 1e-6);
  series.backend_ms.push_back(static_cast<double>(record.frame.backend_host_ns) * 1e-6);
  if (record.frame.estimated_pose) ++series.estimated;
}

void MixRun::add_accuracy(Segment& s) {
  const eval::AlignmentMethod alignment = eval::segment_alignment(!s.dataset.imu().empty());
  for (auto& [mode, p] : s.poses) {
    p.truth.stamp_kind = p.estimate.stamp_kind = eval::StampKind::kSeconds;
    p.truth.source = s.spec.name + " ground truth";
    p.estimate.source = s.spec.name + " estimate";
    const std::optional<eval::EvalResult> r = eval::segment_ate(p.truth, p.estimate, alignment);
    if (!r) continue;
    s.summary.ate_rmse_m[trace::to_string(mode)] = r->ate_m.rmse;
    s.summary.ate_pairs[trace::to_string(mode)] = r->pairs;
    series_[mode].ate.add(*r);
    s.accuracy.emplace(mode, *r);
  }
}

void MixRun::keep_map(Segment& s) {
  const auto it = s.backends.find(BackendMode::Slam);
  if (it == s.backends.end()) return;
  const auto& slam = dynamic_cast<const backend::slam::SlamBackend&>(*it->second);
  auto map = std::make_shared<const backend::slam::Map>(slam.map());
  if (options_.save_maps) {
    const fs::path file = options_.data_dir / fmt::format("{}-map.json", s.world);
    backend::slam::save_map(*map, file);
    s.summary.map_saved = file;
  }
  maps_[s.world] = std::move(map);
}

std::vector<ModeRunSummary> MixRun::mode_summaries() const {
  std::vector<ModeRunSummary> modes;
  for (BackendMode mode : kModes) {
    const auto it = series_.find(mode);
    if (it == series_.end()) continue;
    const ModeSeries& s = it->second;
    ModeRunSummary m;
    m.mode = trace::to_string(mode);
    m.frames = s.backend_ms.size();
    m.estimated_frames = s.estimated;
    m.frontend_ms = frontend::summarize(s.frontend_ms);
    m.backend_ms = frontend::summarize(s.backend_ms);
    for (const auto& [name, values] : s.kernel_ms) {
      std::vector<double> padded = values;
      padded.resize(s.backend_ms.size(), 0.0);
      m.kernel_ms.emplace_back(name, frontend::summarize(padded));
    }
    m.ate_rmse_m = s.ate.rmse();
    m.ate_pairs = s.ate.pairs;
    modes.push_back(std::move(m));
  }
  return modes;
}

}  // namespace

void prepare_mix_data(const MixRunOptions& options, const MixProgress& progress) {
  fs::create_directories(options.data_dir);
  generate_mix_data(
      options.plan, options.data_dir,
      [&](std::string_view run, int done, int total) {
        if (progress) progress(fmt::format("data {}", run), done, total);
      },
      options.generator_threads);
  if (needs_registration(options.plan)) load_or_train_vocabulary(options, progress);
}

namespace {

/// run_mix after its checks: the data, the vocabulary, then every segment into one trace.
MixRunSummary run_mix_in(const MixRunOptions& options, const MixProgress& progress,
                         std::chrono::steady_clock::time_point run_start) {
  const MixPlan& plan = options.plan;
  prepare_mix_data(options, progress);
  std::shared_ptr<const bow::Vocabulary> vocabulary;
  if (needs_registration(plan)) vocabulary = load_or_train_vocabulary(options, progress);

  MixRunSummary summary;
  summary.out = options.out;
  summary.plan = plan.to_string();
  const std::vector<std::unique_ptr<datasets::Dataset>> datasets = open_segments(options);
  TraceSession session(mix_meta(options, datasets),
                       {options.out, options.overwrite, options.frontend, options.host_speed});
  MixRun run(options, std::move(vocabulary), session, progress);
  for (std::size_t si = 0; si < plan.segments.size(); ++si) {
    summary.segments.push_back(run.run_segment(plan.segments[si], *datasets[si]));
  }
  session.finish();
  summary.frames = run.frames();
  summary.modes = run.mode_summaries();
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  return summary;
}

}  // namespace

MixRunSummary run_mix(const MixRunOptions& requested, const MixProgress& progress) {
  const auto run_start = std::chrono::steady_clock::now();
  MixRunOptions options = requested;
  options.vio.precision = options.slam.precision = options.precision;
  const frontend::TracingThreads threads(options.frontend.parallel_images);
  options.frontend.validate();
  options.mode_switch.validate();
  options.vio.validate();
  options.slam.validate();
  trace::TraceWriter::check_output(options.out, options.overwrite);  // before any work
  // A run that fails leaves nothing half written: a data folder this run created goes with it
  // (a folder that was there before is a cache of earlier runs and stays as it is).
  const bool data_dir_is_new = !fs::exists(options.data_dir);
  try {
    return run_mix_in(options, progress, run_start);
  } catch (...) {
    std::error_code ignored;
    if (data_dir_is_new) fs::remove_all(options.data_dir, ignored);
    throw;
  }
}

namespace {

nlohmann::json stats_json(const frontend::SampleStats& s) {
  const double rsd = s.mean > 0 ? s.sd / s.mean : 0.0;
  return {{"mean", s.mean}, {"sd", s.sd},   {"rsd", rsd},
          {"p50", s.p50},   {"p99", s.p99}, {"max", s.max}};
}

}  // namespace

nlohmann::json to_json(const MixRunSummary& s) {
  nlohmann::json segments = nlohmann::json::array();
  for (const SegmentRunSummary& seg : s.segments) {
    segments.push_back({{"name", seg.name},
                        {"scenario", seg.scenario},
                        {"first_frame_id", seg.first_frame_id},
                        {"frames", seg.frames},
                        {"ate_rmse_m", seg.ate_rmse_m},
                        {"frames_by_mode", seg.frames_by_mode},
                        {"registration_failures", seg.registration_failures},
                        {"map_saved", seg.map_saved ? seg.map_saved->string() : ""}});
  }
  nlohmann::json modes = nlohmann::json::object();
  for (const ModeRunSummary& m : s.modes) {
    nlohmann::json kernels = nlohmann::json::object();
    for (const auto& [name, ms] : m.kernel_ms) {
      kernels[name] = stats_json(ms);
      kernels[name]["share"] = m.backend_ms.mean > 0 ? ms.mean / m.backend_ms.mean : 0.0;
    }
    modes[m.mode] = {
        {"frames", m.frames},
        {"estimated_frames", m.estimated_frames},
        {"frontend_ms", stats_json(m.frontend_ms)},
        {"backend_ms", stats_json(m.backend_ms)},
        {"kernel_ms", kernels},
        {"ate_rmse_m", m.ate_rmse_m ? nlohmann::json(*m.ate_rmse_m) : nlohmann::json()},
        {"ate_pairs", m.ate_pairs}};
  }
  return {{"out", s.out.string()},
          {"frames", s.frames},
          {"segments", segments},
          {"modes", modes},
          {"wall_seconds", s.wall_seconds}};
}

std::string format_summary(const MixRunSummary& s) {
  std::string text = fmt::format("trace      {}\n{}", s.out.string(), s.plan);
  for (const SegmentRunSummary& seg : s.segments) {
    std::string modes;
    for (const auto& [mode, n] : seg.frames_by_mode) modes += fmt::format(" {} {}", mode, n);
    text += fmt::format("segment    {:<11} frames by mode:{}; registration failures {}{}\n",
                        seg.name, modes, seg.registration_failures,
                        seg.map_saved ? "; map saved to " + seg.map_saved->string() : "");
  }
  text += fmt::format("\n{:<13} {:>6} {:>9} {:>8} {:>7} {:>9} {:>8} {:>7} {:>9}\n", "mode",
                      "frames", "FE ms", "FE sd", "FE rsd", "BE ms", "BE sd", "BE rsd", "ATE m");
  for (const ModeRunSummary& m : s.modes) {
    const auto rsd = [](const frontend::SampleStats& x) {
      return x.mean > 0 ? x.sd / x.mean : 0.0;
    };
    text += fmt::format(
        "{:<13} {:>6} {:>9.2f} {:>8.2f} {:>6.0f}% {:>9.2f} {:>8.2f} {:>6.0f}% {:>9}\n", m.mode,
        m.frames, m.frontend_ms.mean, m.frontend_ms.sd, 100 * rsd(m.frontend_ms), m.backend_ms.mean,
        m.backend_ms.sd, 100 * rsd(m.backend_ms),
        m.ate_rmse_m ? fmt::format("{:.3f}", *m.ate_rmse_m) : "-");
  }
  for (const ModeRunSummary& m : s.modes) {
    text += fmt::format("\n{} backend kernels (share of the mean backend time {:.2f} ms):\n",
                        m.mode, m.backend_ms.mean);
    for (const auto& [name, ms] : m.kernel_ms) {
      text += fmt::format("  {:<22} {:>8.3f} ms {:>5.1f}%\n", name, ms.mean,
                          m.backend_ms.mean > 0 ? 100 * ms.mean / m.backend_ms.mean : 0.0);
    }
  }
  return text;
}

}  // namespace edx::modes
