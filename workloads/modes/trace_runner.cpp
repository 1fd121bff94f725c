#include "workloads/modes/trace_runner.hpp"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/eval/segment_ate.hpp"
#include "workloads/eval/trajectory.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/modes/pipeline.hpp"
#include "workloads/modes/trace_session.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::modes {
namespace {

using frontend::FrontendFrame;
using frontend::StereoFrontend;
using frontend::summarize;

namespace fs = std::filesystem;

std::string task_key(trace::Task task, trace::Image image) {
  return fmt::format("{}/{}", trace::to_string(task), trace::to_string(image));
}

nlohmann::json stats_json(const SampleStats& s) {
  return {{"mean", s.mean}, {"sd", s.sd},   {"min", s.min},
          {"p50", s.p50},   {"p99", s.p99}, {"max", s.max}};
}

/// The default scenario: outdoor for KITTI and for EuRoC-layout data with GPS, indoor otherwise;
/// the known variant when the frames have a map.
trace::Scenario default_scenario(const TraceRunOptions& options, const datasets::Dataset& dataset,
                                 bool map_available) {
  const bool outdoor = options.format == datasets::DatasetFormat::kKitti || !dataset.gps().empty();
  return outdoor ? (map_available ? trace::Scenario::OutdoorKnown : trace::Scenario::OutdoorUnknown)
                 : (map_available ? trace::Scenario::IndoorKnown : trace::Scenario::IndoorUnknown);
}

/// One `edx trace` run: the dataset, its frontend and backend, the frames' records and the
/// per-frame series the summary is made of.
class TraceRun {
 public:
  /// Opens the dataset and builds the backend. Throws when there are no frames, or when a map
  /// is to be saved without the SLAM backend.
  explicit TraceRun(const TraceRunOptions& options);

  std::size_t frames() const { return frames_; }
  /// The trace's meta for this run.
  TraceRunMeta meta() const;
  /// Frame i through the frontend and the backend: its trace record.
  trace::FrameTrace trace_frame(std::size_t i);
  /// Saves the map (map_out), and the summary of the frames traced, with the accuracy of the
  /// estimate (wall_seconds left to the caller).
  TraceRunSummary finish();

 private:
  void add_frontend_series(const FrontendFrame& result);
  std::optional<eval::EvalResult> accuracy() const;

  const TraceRunOptions& options_;
  std::unique_ptr<datasets::Dataset> dataset_;
  std::size_t frames_;
  std::unique_ptr<backend::Backend> backend_;
  /// Registration localizes in a prebuilt map: the frames have a map (the known scenarios).
  bool map_available_ = false;
  trace::Scenario scenario_ = trace::Scenario::IndoorUnknown;
  const backend::slam::SlamBackend* map_builder_ = nullptr;  ///< the backend when it is SLAM's
  TraceRunSummary summary_;
  /// Made last, so that the dataset's and the backend's errors come first.
  std::optional<StereoFrontend> frontend_;
  std::int64_t previous_t_ns_ = std::numeric_limits<std::int64_t>::min();

  // Per-frame series.
  std::vector<std::vector<double>> task_ms_;
  std::vector<std::pair<trace::Task, trace::Image>> task_kinds_;
  std::vector<double> frontend_ms_, left_, right_, tracked_, added_, stereo_, backend_ms_;
  KernelSeries kernel_ms_;
  eval::Trajectory truth_poses_, estimated_poses_;
};

TraceRun::TraceRun(const TraceRunOptions& options)
    : options_(options),
      dataset_(datasets::open_dataset(options.dataset_path, options.format, options.dataset)),
      frames_(std::min(dataset_->frame_count(),
                       options.max_frames.value_or(std::numeric_limits<std::size_t>::max()))) {
  if (frames_ == 0) {
    throw std::runtime_error(fmt::format("{}: no stereo frames to process", dataset_->name()));
  }
  if (options.make_backend) backend_ = options.make_backend(*dataset_);
  map_available_ = backend_ && backend_->mode() == trace::BackendMode::Registration;
  scenario_ = options.scenario.value_or(default_scenario(options, *dataset_, map_available_));
  const datasets::CameraIntrinsics& k = dataset_->calibration().rectified;
  summary_.out = options.out;
  summary_.dataset = dataset_->name();
  summary_.sequence = sequence_name(options.dataset_path, options.format, options.dataset);
  summary_.resolution = fmt::format("{}x{}", k.width, k.height);
  summary_.scenario = trace::to_string(scenario_);
  summary_.backend_mode = trace::to_string(backend_ ? backend_->mode() : trace::BackendMode::None);
  map_builder_ = dynamic_cast<const backend::slam::SlamBackend*>(backend_.get());
  if (options.map_out && !map_builder_) {
    throw std::runtime_error(fmt::format("{}: saving a map needs the slam backend (got {})",
                                         options.map_out->string(), summary_.backend_mode));
  }
  truth_poses_.source = dataset_->name() + " ground truth";
  estimated_poses_.source = "the estimate of " + dataset_->name();
  truth_poses_.stamp_kind = estimated_poses_.stamp_kind = eval::StampKind::kSeconds;
  frontend_.emplace(options.frontend,
                    frontend::StereoCamera{k.fx, dataset_->calibration().baseline_m});
}

TraceRunMeta TraceRun::meta() const {
  const datasets::StereoCalibration& calibration = dataset_->calibration();
  const datasets::CameraIntrinsics& k = calibration.rectified;
  TraceRunMeta meta;
  meta.dataset = summary_.dataset;
  meta.sequence = summary_.sequence;
  meta.resolution = summary_.resolution;
  meta.camera_model =
      fmt::format("pinhole-rectified fx={:.4f} fy={:.4f} cx={:.4f} cy={:.4f} b={:.6f}m", k.fx, k.fy,
                  k.cx, k.cy, calibration.baseline_m);
  meta.pipeline_params = {{"backend_mode", summary_.backend_mode}};
  meta.frames = frames_;
  meta.precision = options_.precision;
  return meta;
}

trace::FrameTrace TraceRun::trace_frame(std::size_t i) {
  const datasets::StereoFrame images = dataset_->load_frame(i);
  FrontendFrame result;
  try {
    result = frontend_->process(images.left, images.right);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(fmt::format("{}: {}", dataset_->name(), e.what()));
  }

  const auto frame_id = static_cast<std::int64_t>(i);
  trace::FrameTrace record;
  record.frame.frame_id = frame_id;
  record.frame.timestamp_ns = images.t_ns;
  record.frame.sequence = summary_.sequence;
  record.frame.scenario = scenario_;
  record.frame.mode = backend_ ? backend_->mode() : trace::BackendMode::None;
  record.frame.gps_available = gps_near(dataset_->gps(), images.t_ns);
  record.frame.map_available = map_available_;
  if (const std::optional<Eigen::Isometry3d> truth = ground_truth_at(*dataset_, images.t_ns)) {
    record.frame.ground_truth_pose = to_pose_array(*truth);
    truth_poses_.poses.push_back(stamped(images.t_ns, frame_id, *truth));
    ++summary_.ground_truth_frames;
  }
  record.frame.frontend_host_ns = result.host_ns;
  record.tasks = result.tasks;
  if (backend_) {
    backend::BackendOutput output =
        run_backend_on_frame(*backend_, *dataset_, images, result, previous_t_ns_, record.frame);
    if (output.T_world_body) {
      record.frame.estimated_pose = to_pose_array(*output.T_world_body);
      estimated_poses_.poses.push_back(stamped(images.t_ns, frame_id, *output.T_world_body));
    }
    add_kernel_times(kernel_ms_, backend_ms_.size(), output.kernels);
    backend_ms_.push_back(static_cast<double>(record.frame.backend_host_ns) * 1e-6);
    record.kernels = std::move(output.kernels);
  }
  previous_t_ns_ = images.t_ns;
  add_frontend_series(result);
  return record;
}

void TraceRun::add_frontend_series(const FrontendFrame& result) {
  if (task_ms_.empty()) {
    task_ms_.resize(result.tasks.size());
    for (const trace::TaskRecord& t : result.tasks) task_kinds_.emplace_back(t.task, t.image);
  }
  for (std::size_t t = 0; t < result.tasks.size() && t < task_ms_.size(); ++t) {
    task_ms_[t].push_back(static_cast<double>(result.tasks[t].host_ns) * 1e-6);
  }
  frontend_ms_.push_back(static_cast<double>(result.host_ns) * 1e-6);
  left_.push_back(result.stats.left_keypoints);
  right_.push_back(result.stats.right_keypoints);
  tracked_.push_back(result.stats.tracked);
  added_.push_back(result.stats.new_features);
  stereo_.push_back(result.stats.stereo_matches);
}

TraceRunSummary TraceRun::finish() {
  TraceRunSummary summary = std::move(summary_);
  if (options_.map_out) {
    const backend::slam::Map map = map_builder_->map();
    backend::slam::save_map(map, *options_.map_out);
    summary.map_out = options_.map_out;
    summary.map_keyframes = map.keyframes.size();
    summary.map_landmarks = map.landmarks.size();
  }
  summary.frames = frames_;
  for (std::size_t t = 0; t < task_ms_.size(); ++t) {
    summary.tasks.push_back({task_kinds_[t].first, task_kinds_[t].second, summarize(task_ms_[t])});
  }
  summary.frontend_ms = summarize(frontend_ms_);
  summary.left_keypoints = summarize(left_);
  summary.right_keypoints = summarize(right_);
  summary.tracked = summarize(tracked_);
  summary.new_features = summarize(added_);
  summary.stereo_matches = summarize(stereo_);
  summary.backend_ms = summarize(backend_ms_);
  summary.estimated_frames = estimated_poses_.poses.size();
  for (const auto& [name, series] : kernel_ms_)
    summary.kernel_ms.emplace_back(name, summarize(series));
  summary.accuracy = accuracy();
  return summary;
}

std::optional<eval::EvalResult> TraceRun::accuracy() const {
  if (!backend_) return std::nullopt;
  return eval::segment_ate(
      truth_poses_, estimated_poses_,
      options_.alignment.value_or(eval::segment_alignment(!dataset_->imu().empty())));
}
}  // namespace

std::string sequence_name(const fs::path& dataset_path, datasets::DatasetFormat format,
                          const datasets::DatasetOptions& options) {
  fs::path path = fs::weakly_canonical(dataset_path);
  if (path.filename().empty()) path = path.parent_path();  // trailing separator
  std::string name;
  if (format == datasets::DatasetFormat::kKitti && !options.kitti_sequence.empty()) {
    name = options.kitti_sequence;
  } else {
    if (path.filename() == "mav0") path = path.parent_path();
    name = path.filename().string();
  }
  return fmt::format("{}:{}", datasets::to_string(format), name);
}

TraceRunSummary run_trace(const TraceRunOptions& options, const TraceProgress& progress) {
  const auto run_start = std::chrono::steady_clock::now();
  const frontend::TracingThreads threads(options.frontend.parallel_images);
  options.frontend.validate();
  trace::TraceWriter::check_output(options.out, options.overwrite);  // before any work
  TraceRun run(options);
  TraceSession session(run.meta(),
                       {options.out, options.overwrite, options.frontend, options.host_speed});
  for (std::size_t i = 0; i < run.frames(); ++i) {
    session.append(run.trace_frame(i));
    if (progress) progress(i + 1, run.frames());
  }
  session.finish();
  TraceRunSummary summary = run.finish();
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  return summary;
}

nlohmann::json backend_json(const TraceRunSummary& s) {
  nlohmann::json j = {{"mode", s.backend_mode}};
  if (s.backend_mode == "none") return j;
  j["backend_ms"] = stats_json(s.backend_ms);
  j["estimated_frames"] = s.estimated_frames;
  nlohmann::json kernels = nlohmann::json::object();
  for (const auto& [name, ms] : s.kernel_ms) kernels[name] = stats_json(ms);
  j["kernel_ms"] = kernels;
  if (s.accuracy) {
    const eval::EvalResult& a = *s.accuracy;
    j["accuracy"] = {{"alignment", eval::alignment_method_name(a.alignment)},
                     {"pairs", a.pairs},
                     {"ate_rmse_m", a.ate_m.rmse},
                     {"rpe_trans_mean_m", a.rpe_trans_m.mean},
                     {"rpe_rot_mean_deg", a.rpe_rot_deg.mean},
                     {"gt_length_m", a.gt_length_m}};
  }
  if (s.map_out) {
    j["map"] = {{"file", s.map_out->string()},
                {"keyframes", s.map_keyframes},
                {"landmarks", s.map_landmarks}};
  }
  return j;
}

nlohmann::json to_json(const TraceRunSummary& s) {
  nlohmann::json tasks = nlohmann::json::object();
  for (const TaskTimeSummary& t : s.tasks) tasks[task_key(t.task, t.image)] = stats_json(t.ms);
  return {
      {"out", s.out.string()},
      {"dataset", s.dataset},
      {"sequence", s.sequence},
      {"resolution", s.resolution},
      {"scenario", s.scenario},
      {"frames", s.frames},
      {"ground_truth_frames", s.ground_truth_frames},
      {"task_ms", tasks},
      {"frontend_ms", stats_json(s.frontend_ms)},
      {"per_frame",
       {{"left_keypoints", stats_json(s.left_keypoints)},
        {"right_keypoints", stats_json(s.right_keypoints)},
        {"tracked", stats_json(s.tracked)},
        {"new_features", stats_json(s.new_features)},
        {"stereo_matches", stats_json(s.stereo_matches)}}},
      {"wall_seconds", s.wall_seconds},
      {"backend", backend_json(s)},
  };
}

std::string format_summary(const TraceRunSummary& s) {
  std::string text;
  text += fmt::format("trace      {}\n", s.out.string());
  text +=
      fmt::format("dataset    {} ({}, {}, {})\n", s.dataset, s.sequence, s.resolution, s.scenario);
  text += fmt::format("frames     {} ({} with ground truth) in {:.1f} s\n", s.frames,
                      s.ground_truth_frames, s.wall_seconds);
  text += fmt::format(
      "per frame  left keypoints {:.0f}, right keypoints {:.0f}, tracked {:.0f}, new {:.0f}, "
      "stereo matches {:.0f} (means)\n",
      s.left_keypoints.mean, s.right_keypoints.mean, s.tracked.mean, s.new_features.mean,
      s.stereo_matches.mean);
  text += fmt::format("\n{:<22} {:>9} {:>9} {:>9} {:>9}\n", "task", "mean ms", "sd ms", "p99 ms",
                      "max ms");
  for (const TaskTimeSummary& t : s.tasks) {
    text += fmt::format("{:<22} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}\n", task_key(t.task, t.image),
                        t.ms.mean, t.ms.sd, t.ms.p99, t.ms.max);
  }
  text += fmt::format("{:<22} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}\n", "frontend",
                      s.frontend_ms.mean, s.frontend_ms.sd, s.frontend_ms.p99, s.frontend_ms.max);
  if (s.backend_mode == "none") return text;
  for (const auto& [name, ms] : s.kernel_ms) {
    text += fmt::format("{:<22} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}\n", name, ms.mean, ms.sd,
                        ms.p99, ms.max);
  }
  text += fmt::format("{:<22} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f}\n", "backend", s.backend_ms.mean,
                      s.backend_ms.sd, s.backend_ms.p99, s.backend_ms.max);
  text += fmt::format("\nbackend    {}: pose on {} of {} frames\n", s.backend_mode,
                      s.estimated_frames, s.frames);
  if (s.accuracy) {
    const eval::EvalResult& a = *s.accuracy;
    text += fmt::format(
        "accuracy   ATE RMSE {:.3f} m over {} frames ({} alignment, {:.1f} m travelled); "
        "RPE {:.4f} m, {:.3f} deg per frame\n",
        a.ate_m.rmse, a.pairs, eval::alignment_method_name(a.alignment), a.gt_length_m,
        a.rpe_trans_m.mean, a.rpe_rot_deg.mean);
  }
  if (s.map_out) {
    text += fmt::format("map        {}: {} keyframes, {} landmarks\n", s.map_out->string(),
                        s.map_keyframes, s.map_landmarks);
  }
  return text;
}

}  // namespace edx::modes
