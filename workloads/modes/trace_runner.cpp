#include "workloads/modes/trace_runner.hpp"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cstdlib>
#include <limits>
#include <map>
#include <span>
#include <stdexcept>

#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/eval/trajectory.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/frontend/trace_meta.hpp"
#include "workloads/modes/host_speed_meter.hpp"
#include "workloads/modes/pipeline.hpp"
#include "workloads/trace/host_clock.hpp"
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
  const std::unique_ptr<datasets::Dataset> dataset =
      datasets::open_dataset(options.dataset_path, options.format, options.dataset);
  std::size_t frames = dataset->frame_count();
  if (options.max_frames) frames = std::min(frames, *options.max_frames);
  if (frames == 0) {
    throw std::runtime_error(fmt::format("{}: no stereo frames to process", dataset->name()));
  }
  const datasets::StereoCalibration& calibration = dataset->calibration();
  const datasets::CameraIntrinsics& k = calibration.rectified;
  std::unique_ptr<backend::Backend> backend;
  if (options.make_backend) backend = options.make_backend(*dataset);
  // Registration localizes in a prebuilt map: the frames have a map (the known scenarios).
  const bool map_available = backend && backend->mode() == trace::BackendMode::Registration;
  const bool outdoor = options.format == datasets::DatasetFormat::kKitti || !dataset->gps().empty();
  const trace::Scenario scenario = options.scenario.value_or(
      outdoor ? (map_available ? trace::Scenario::OutdoorKnown : trace::Scenario::OutdoorUnknown)
              : (map_available ? trace::Scenario::IndoorKnown : trace::Scenario::IndoorUnknown));

  TraceRunSummary summary;
  summary.out = options.out;
  summary.dataset = dataset->name();
  summary.sequence = sequence_name(options.dataset_path, options.format, options.dataset);
  summary.resolution = fmt::format("{}x{}", k.width, k.height);
  summary.scenario = trace::to_string(scenario);

  trace::TraceMeta meta = frontend::host_and_build_meta();
  meta["dataset"] = summary.dataset;
  meta["sequence"] = summary.sequence;
  meta["resolution"] = summary.resolution;
  meta["camera_model"] =
      fmt::format("pinhole-rectified fx={:.4f} fy={:.4f} cx={:.4f} cy={:.4f} b={:.6f}m", k.fx, k.fy,
                  k.cx, k.cy, calibration.baseline_m);
  summary.backend_mode = trace::to_string(backend ? backend->mode() : trace::BackendMode::None);
  const auto* map_builder = dynamic_cast<const backend::slam::SlamBackend*>(backend.get());
  if (options.map_out && !map_builder) {
    throw std::runtime_error(fmt::format("{}: saving a map needs the slam backend (got {})",
                                         options.map_out->string(), summary.backend_mode));
  }
  meta["pipeline_params"] = nlohmann::json{
      {"frontend", frontend::to_json(options.frontend)},
      {"backend_mode",
       summary.backend_mode}}.dump();
  meta["frames"] = std::to_string(frames);
  meta["opencv_version"] = CV_VERSION;

  // How fast this machine is, sampled over the whole run (host_speed_meter.hpp).
  HostSpeedMeterOptions host_speed_options = options.host_speed;
  host_speed_options.parallel_images = options.frontend.parallel_images;
  HostSpeedMeter host_speed(host_speed_options);
  host_speed.start();
  meta["host_speed"] = trace::to_meta_value(host_speed.result());

  trace::TraceWriterOptions writer_options;
  writer_options.overwrite = options.overwrite;
  trace::TraceWriter writer(options.out, meta, writer_options);
  StereoFrontend frontend(options.frontend, {k.fx, calibration.baseline_m});

  std::vector<std::vector<double>> task_ms;
  std::vector<std::pair<trace::Task, trace::Image>> task_kinds;
  std::vector<double> frontend_ms, left, right, tracked, added, stereo, backend_ms;
  std::map<std::string, std::vector<double>> kernel_ms;  // name -> ms per frame (0 when absent)
  eval::Trajectory truth_poses, estimated_poses;
  truth_poses.source = dataset->name() + " ground truth";
  estimated_poses.source = "the estimate of " + dataset->name();
  truth_poses.stamp_kind = estimated_poses.stamp_kind = eval::StampKind::kSeconds;
  std::int64_t previous_t_ns = std::numeric_limits<std::int64_t>::min();
  for (std::size_t i = 0; i < frames; ++i) {
    const datasets::StereoFrame images = dataset->load_frame(i);
    FrontendFrame result;
    try {
      result = frontend.process(images.left, images.right);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("{}: {}", dataset->name(), e.what()));
    }

    trace::FrameTrace record;
    record.frame.frame_id = static_cast<std::int64_t>(i);
    record.frame.timestamp_ns = images.t_ns;
    record.frame.sequence = summary.sequence;
    record.frame.scenario = scenario;
    record.frame.mode = backend ? backend->mode() : trace::BackendMode::None;
    record.frame.gps_available = gps_near(dataset->gps(), images.t_ns);
    record.frame.map_available = map_available;
    if (const auto truth = datasets::interpolate_ground_truth(dataset->ground_truth(), images.t_ns,
                                                              kMaxGroundTruthGapNs)) {
      record.frame.ground_truth_pose = to_pose_array(truth->T_world_body);
      truth_poses.poses.push_back(
          stamped(images.t_ns, static_cast<std::int64_t>(i), truth->T_world_body));
      ++summary.ground_truth_frames;
    }
    record.frame.frontend_host_ns = result.host_ns;
    record.tasks = result.tasks;
    if (backend) {
      backend::BackendInput input;
      input.t_ns = images.t_ns;
      input.frontend = &result;
      input.left_image = &images.left;
      input.imu = between(dataset->imu(), previous_t_ns, images.t_ns);
      input.gps = between(dataset->gps(), previous_t_ns, images.t_ns);
      auto [output, backend_ns] = run_backend_timed(*backend, input);
      record.frame.backend_host_ns = backend_ns;
      record.frame.backend_status = output.status;
      if (output.T_world_body) {
        record.frame.estimated_pose = to_pose_array(*output.T_world_body);
        estimated_poses.poses.push_back(
            stamped(images.t_ns, static_cast<std::int64_t>(i), *output.T_world_body));
      }
      for (auto& [name, series] : kernel_ms) series.push_back(0.0);
      for (const trace::KernelRecord& kernel : output.kernels) {
        auto& series = kernel_ms[kernel.kernel];
        series.resize(backend_ms.size() + 1, 0.0);
        series.back() += static_cast<double>(kernel.host_ns) * 1e-6;
      }
      backend_ms.push_back(static_cast<double>(record.frame.backend_host_ns) * 1e-6);
      record.kernels = std::move(output.kernels);
    }
    previous_t_ns = images.t_ns;
    writer.append(record);
    host_speed.after_frame(record.frame.frontend_host_ns + record.frame.backend_host_ns);

    if (task_ms.empty()) {
      task_ms.resize(result.tasks.size());
      for (const trace::TaskRecord& t : result.tasks) task_kinds.emplace_back(t.task, t.image);
    }
    for (std::size_t t = 0; t < result.tasks.size() && t < task_ms.size(); ++t) {
      task_ms[t].push_back(static_cast<double>(result.tasks[t].host_ns) * 1e-6);
    }
    frontend_ms.push_back(static_cast<double>(result.host_ns) * 1e-6);
    left.push_back(result.stats.left_keypoints);
    right.push_back(result.stats.right_keypoints);
    tracked.push_back(result.stats.tracked);
    added.push_back(result.stats.new_features);
    stereo.push_back(result.stats.stereo_matches);
    if (progress) progress(i + 1, frames);
  }
  host_speed.finish_into(writer);
  writer.finish();
  if (options.map_out) {
    const backend::slam::Map map = map_builder->map();
    backend::slam::save_map(map, *options.map_out);
    summary.map_out = options.map_out;
    summary.map_keyframes = map.keyframes.size();
    summary.map_landmarks = map.landmarks.size();
  }

  summary.frames = frames;
  for (std::size_t t = 0; t < task_ms.size(); ++t) {
    summary.tasks.push_back({task_kinds[t].first, task_kinds[t].second, summarize(task_ms[t])});
  }
  summary.frontend_ms = summarize(frontend_ms);
  summary.left_keypoints = summarize(left);
  summary.right_keypoints = summarize(right);
  summary.tracked = summarize(tracked);
  summary.new_features = summarize(added);
  summary.stereo_matches = summarize(stereo);
  summary.backend_ms = summarize(backend_ms);
  summary.estimated_frames = estimated_poses.poses.size();
  for (const auto& [name, series] : kernel_ms)
    summary.kernel_ms.emplace_back(name, summarize(series));
  if (backend) {
    eval::EvalOptions eval_options;
    eval_options.alignment = options.alignment.value_or(
        dataset->imu().empty() ? eval::AlignmentMethod::kSe3 : eval::AlignmentMethod::kPosYaw);
    eval_options.t_max_diff_s = 1e-3;  // both sides are stamped with the frame times
    if (estimated_poses.poses.size() >= eval::min_pairs_for(eval_options.alignment) &&
        !truth_poses.poses.empty()) {
      summary.accuracy = eval::evaluate(truth_poses, estimated_poses, eval_options);
    }
  }
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
