#include "workloads/modes/mix_runner.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/version.hpp>
#include <stdexcept>

#include "workloads/backend/registration/bow/training.hpp"
#include "workloads/backend/registration/registration_backend.hpp"
#include "workloads/backend/slam/slam_backend.hpp"
#include "workloads/backend/vio/vio_backend.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"
#include "workloads/frontend/trace_meta.hpp"
#include "workloads/modes/host_speed_meter.hpp"
#include "workloads/modes/pipeline.hpp"
#include "workloads/trace/host_clock.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::modes {
namespace {

namespace fs = std::filesystem;
using trace::BackendMode;

constexpr BackendMode kModes[] = {BackendMode::Registration, BackendMode::Vio, BackendMode::Slam};

/// Per-frame series of one mode.
struct ModeSeries {
  std::vector<double> frontend_ms, backend_ms;
  std::map<std::string, std::vector<double>> kernel_ms;  // 0 on frames where it did not run
  std::size_t estimated = 0;
  double squared_error_sum = 0;  // sum over segments of pairs * rmse^2
  std::size_t pairs = 0;
};

/// Estimated and true poses of one (segment, mode), evaluated once the segment ends.
struct PosePairs {
  eval::Trajectory truth, estimate;
};

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
  synthetic::GenerateOptions world;
  world.scenario = synthetic::Scenario::kIndoorUnknown;
  world.frames = 100;
  world.resolution = plan.resolution;
  world.seed = seed;
  world.threads = options.generator_threads;
  world.out = options.data_dir / fmt::format("vocabulary-world-{}x{}-s{}", plan.resolution.width,
                                             plan.resolution.height, seed);
  if (!fs::exists(world.out / "edx_gen.yaml")) {
    synthetic::generate_dataset(world, [&](std::string_view, int done, int total) {
      if (progress) progress("vocabulary data", done, total);
    });
  }
  bow::TrainingOptions training;
  training.datasets = {{world.out, datasets::DatasetFormat::kEuroc, {}}};
  training.frame_stride = 4;
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

MixRunSummary run_mix(const MixRunOptions& options, const MixProgress& progress) {
  const auto run_start = std::chrono::steady_clock::now();
  const frontend::TracingThreads threads(options.frontend.parallel_images);
  options.frontend.validate();
  options.mode_switch.validate();
  options.vio.validate();
  options.slam.validate();
  trace::TraceWriter::check_output(options.out, options.overwrite);  // before any work
  const MixPlan& plan = options.plan;
  prepare_mix_data(options, progress);
  std::shared_ptr<const bow::Vocabulary> vocabulary;
  if (needs_registration(plan)) vocabulary = load_or_train_vocabulary(options, progress);

  MixRunSummary summary;
  summary.out = options.out;
  summary.plan = plan.to_string();

  trace::TraceMeta meta = frontend::host_and_build_meta();
  meta["dataset"] = fmt::format("synthetic mix {}", plan.name);
  meta["sequence"] = fmt::format("mix:{}", plan.name);
  meta["resolution"] = fmt::format("{}x{}", plan.resolution.width, plan.resolution.height);
  nlohmann::json cameras = nlohmann::json::array();
  nlohmann::json segments_json = nlohmann::json::array();
  std::vector<std::unique_ptr<datasets::Dataset>> datasets_by_segment;
  for (const MixSegment& s : plan.segments) {
    const fs::path mav0 = segment_mav0(plan, s, options.data_dir);
    datasets_by_segment.push_back(
        datasets::open_dataset(mav0.parent_path(), datasets::DatasetFormat::kEuroc));
    const datasets::CameraIntrinsics& k = datasets_by_segment.back()->calibration().rectified;
    cameras.push_back(fmt::format(
        "{}: pinhole-rectified fx={:.4f} fy={:.4f} cx={:.4f} cy={:.4f} "
        "b={:.6f}m",
        s.name, k.fx, k.fy, k.cx, k.cy, datasets_by_segment.back()->calibration().baseline_m));
    segments_json.push_back({{"name", s.name},
                             {"scenario", trace::to_string(s.scenario)},
                             {"frames", s.frames},
                             {"data", mav0.string()}});
  }
  meta["camera_model"] = cameras.dump();
  meta["pipeline_params"] = nlohmann::json{
      {"frontend", frontend::to_json(options.frontend)},
      {"backend_mode", "mixed"},
      {"mix", plan.name},
      {"segments", segments_json},
      {"mode_switch", options.mode_switch.to_string()},
      {"vio", options.vio.to_json()},
      {"slam",
       options.slam.to_json()}}.dump();
  meta["frames"] = std::to_string(plan.total_frames());
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

  std::map<BackendMode, ModeSeries> series;
  std::map<std::string, std::shared_ptr<const backend::slam::Map>> maps;  // by world
  std::int64_t frame_id = 0;
  for (std::size_t si = 0; si < plan.segments.size(); ++si) {
    const MixSegment& segment = plan.segments[si];
    const datasets::Dataset& dataset = *datasets_by_segment[si];
    const std::string world = world_key(plan, segment);
    const datasets::StereoCalibration& calibration = dataset.calibration();
    frontend::StereoFrontend frontend(options.frontend,
                                      {calibration.rectified.fx, calibration.baseline_m});
    ModeSwitch mode_switch(options.mode_switch, maps.count(world) > 0);
    std::map<BackendMode, std::unique_ptr<backend::Backend>> backends;
    std::map<BackendMode, PosePairs> poses;
    SegmentRunSummary segment_summary;
    segment_summary.name = segment.name;
    segment_summary.scenario = trace::to_string(segment.scenario);
    const std::string sequence =
        fmt::format("synthetic:{}:{}", world, segment.run.empty() ? "run" : segment.run);

    const std::size_t frames =
        std::min<std::size_t>(dataset.frame_count(), static_cast<std::size_t>(segment.frames));
    std::int64_t previous_t_ns = std::numeric_limits<std::int64_t>::min();
    for (std::size_t i = 0; i < frames; ++i) {
      const datasets::StereoFrame images = dataset.load_frame(i);
      frontend::FrontendFrame result = frontend.process(images.left, images.right);
      const ModeDecision decision = mode_switch.decide(
          images.t_ns,
          between(dataset.gps(), std::numeric_limits<std::int64_t>::min(), images.t_ns));
      std::unique_ptr<backend::Backend>& backend = backends[decision.mode];
      if (!backend) {
        switch (decision.mode) {
          case BackendMode::Vio:
            backend = backend::vio::make_vio_backend(dataset, options.vio);
            break;
          case BackendMode::Slam:
            backend = backend::slam::make_slam_backend(dataset, options.slam);
            break;
          case BackendMode::Registration:
            backend = backend::registration::make_registration_backend(
                dataset, backend::registration::RegistrationOptions{}, maps.at(world), vocabulary);
            break;
          case BackendMode::None:
            break;
        }
      }

      trace::FrameTrace record;
      record.frame.frame_id = frame_id++;
      record.frame.timestamp_ns = images.t_ns;
      record.frame.sequence = sequence;
      record.frame.scenario = segment.scenario;
      record.frame.mode = decision.mode;
      record.frame.gps_available = gps_near(dataset.gps(), images.t_ns);
      record.frame.map_available = decision.map != MapUse::kNone;
      record.frame.frontend_host_ns = result.host_ns;
      record.tasks = result.tasks;
      const std::optional<Eigen::Isometry3d> truth = ground_truth_at(dataset, images.t_ns);
      if (truth) record.frame.ground_truth_pose = to_pose_array(*truth);

      backend::BackendInput input;
      input.t_ns = images.t_ns;
      input.frontend = &result;
      input.left_image = &images.left;
      input.imu = between(dataset.imu(), previous_t_ns, images.t_ns);
      input.gps = between(dataset.gps(), previous_t_ns, images.t_ns);
      auto [output, backend_ns] = run_backend_timed(*backend, input);
      record.frame.backend_host_ns = backend_ns;
      record.frame.backend_status = output.status;
      if (decision.mode == BackendMode::Registration) {
        mode_switch.report_registration(output.T_world_body.has_value());
        if (!output.T_world_body) ++segment_summary.registration_failures;
      }

      ModeSeries& s = series[decision.mode];
      for (auto& [name, values] : s.kernel_ms) values.push_back(0.0);
      for (const trace::KernelRecord& kernel : output.kernels) {
        auto& values = s.kernel_ms[kernel.kernel];
        values.resize(s.backend_ms.size() + 1, 0.0);
        values.back() += static_cast<double>(kernel.host_ns) * 1e-6;
      }
      s.frontend_ms.push_back(static_cast<double>(result.host_ns) * 1e-6);
      s.backend_ms.push_back(static_cast<double>(record.frame.backend_host_ns) * 1e-6);
      if (output.T_world_body) {
        ++s.estimated;
        record.frame.estimated_pose = to_pose_array(*output.T_world_body);
        if (truth) {
          PosePairs& p = poses[decision.mode];
          p.truth.poses.push_back(stamped(images.t_ns, record.frame.frame_id, *truth));
          p.estimate.poses.push_back(
              stamped(images.t_ns, record.frame.frame_id, *output.T_world_body));
        }
      }
      record.kernels = std::move(output.kernels);
      writer.append(record);
      host_speed.after_frame(record.frame.frontend_host_ns + record.frame.backend_host_ns);
      ++segment_summary.frames_by_mode[trace::to_string(decision.mode)];
      previous_t_ns = images.t_ns;
      if (progress) progress(segment.name, i + 1, frames);
    }
    segment_summary.frames = frames;

    // Accuracy of each mode on this segment, aligned on its own.
    for (auto& [mode, p] : poses) {
      eval::EvalOptions eval_options;
      eval_options.alignment =
          dataset.imu().empty() ? eval::AlignmentMethod::kSe3 : eval::AlignmentMethod::kPosYaw;
      eval_options.t_max_diff_s = 1e-3;
      if (p.estimate.poses.size() < eval::min_pairs_for(eval_options.alignment)) continue;
      p.truth.stamp_kind = p.estimate.stamp_kind = eval::StampKind::kSeconds;
      p.truth.source = segment.name + " ground truth";
      p.estimate.source = segment.name + " estimate";
      const eval::EvalResult r = eval::evaluate(p.truth, p.estimate, eval_options);
      series[mode].squared_error_sum += static_cast<double>(r.pairs) * r.ate_m.rmse * r.ate_m.rmse;
      series[mode].pairs += r.pairs;
    }
    // The SLAM map of this world, for later segments in it.
    if (const auto it = backends.find(BackendMode::Slam); it != backends.end()) {
      const auto& slam = dynamic_cast<const backend::slam::SlamBackend&>(*it->second);
      auto map = std::make_shared<const backend::slam::Map>(slam.map());
      if (options.save_maps) {
        const fs::path file = options.data_dir / fmt::format("{}-map.json", world);
        backend::slam::save_map(*map, file);
        segment_summary.map_saved = file;
      }
      maps[world] = std::move(map);
    }
    summary.segments.push_back(std::move(segment_summary));
  }
  host_speed.finish_into(writer);
  writer.finish();

  summary.frames = static_cast<std::size_t>(frame_id);
  for (BackendMode mode : kModes) {
    const auto it = series.find(mode);
    if (it == series.end()) continue;
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
    if (s.pairs > 0) {
      m.ate_rmse_m = std::sqrt(s.squared_error_sum / static_cast<double>(s.pairs));
      m.ate_pairs = s.pairs;
    }
    summary.modes.push_back(std::move(m));
  }
  summary.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
  return summary;
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
                        {"frames", seg.frames},
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
