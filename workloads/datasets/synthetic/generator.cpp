#include "workloads/datasets/synthetic/generator.hpp"

#include <fmt/format.h>

#include <chrono>
#include <stdexcept>
#include <system_error>

#include "workloads/datasets/synthetic/euroc_writer.hpp"
#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"

namespace edx::synthetic {

namespace fs = std::filesystem;

Scenario parse_scenario(std::string_view text) {
  if (text == "indoor_unknown") return Scenario::kIndoorUnknown;
  if (text == "indoor_known") return Scenario::kIndoorKnown;
  if (text == "outdoor_unknown") return Scenario::kOutdoorUnknown;
  if (text == "outdoor_known") return Scenario::kOutdoorKnown;
  throw std::runtime_error("scenario '" + std::string(text) +
                           "': expected indoor_unknown, indoor_known, outdoor_unknown or "
                           "outdoor_known");
}

std::string_view to_string(Scenario scenario) {
  switch (scenario) {
    case Scenario::kIndoorUnknown:
      return "indoor_unknown";
    case Scenario::kIndoorKnown:
      return "indoor_known";
    case Scenario::kOutdoorUnknown:
      return "outdoor_unknown";
    case Scenario::kOutdoorKnown:
      return "outdoor_known";
  }
  return "unknown";
}

RevisitMode parse_loc_route(std::string_view text) {
  if (text == "retraverse") return RevisitMode::kRetraverse;
  if (text == "diverge") return RevisitMode::kDiverge;
  throw std::runtime_error("loc route '" + std::string(text) + "': expected retraverse or diverge");
}

std::string_view to_string(RevisitMode mode) {
  return mode == RevisitMode::kRetraverse ? "retraverse" : "diverge";
}

bool is_outdoor(Scenario s) {
  return s == Scenario::kOutdoorUnknown || s == Scenario::kOutdoorKnown;
}
bool has_map_run(Scenario s) { return s == Scenario::kIndoorKnown || s == Scenario::kOutdoorKnown; }

Scene build_scene(Scenario scenario, std::uint64_t seed) {
  const std::uint64_t world_seed = derive_seed(seed, "world");
  return is_outdoor(scenario) ? build_street(world_seed) : build_warehouse(world_seed);
}

StereoRig resolve_rig(const GenerateOptions& options) {
  RigKind kind = is_outdoor(options.scenario) ? RigKind::kCar : RigKind::kEuroc;
  if (options.rig) {
    kind = *options.rig;
  } else if (options.resolution) {
    if (*options.resolution == native_resolution(RigKind::kEuroc)) kind = RigKind::kEuroc;
    if (*options.resolution == native_resolution(RigKind::kCar)) kind = RigKind::kCar;
  }
  return make_rig(kind, options.resolution.value_or(native_resolution(kind)));
}

namespace {

/// Removes a temporary output folder unless released.
class TempDirGuard {
 public:
  explicit TempDirGuard(fs::path dir) : dir_(std::move(dir)) {}
  ~TempDirGuard() {
    if (!dir_.empty()) {
      std::error_code ec;
      fs::remove_all(dir_, ec);
    }
  }
  TempDirGuard(const TempDirGuard&) = delete;
  TempDirGuard& operator=(const TempDirGuard&) = delete;
  void release() { dir_.clear(); }

 private:
  fs::path dir_;
};

void check_output(const fs::path& out, bool force) {
  if (out.empty()) throw std::runtime_error("output directory: empty path");
  std::error_code ec;
  const auto status = fs::status(out, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) {
    throw std::runtime_error(out.string() + ": exists and is not a directory");
  }
  if (!fs::is_empty(out, ec) && !force) {
    throw std::runtime_error(out.string() +
                             ": exists and is not empty (use --force to replace it)");
  }
}

void validate(const GenerateOptions& o) {
  if (o.frames < 1) {
    throw std::runtime_error("frames: expected a positive number of frames, got " +
                             std::to_string(o.frames));
  }
  if (o.frames > 1'000'000) throw std::runtime_error("frames: at most 1000000");
  if (o.map_frames) {
    if (!has_map_run(o.scenario)) {
      throw std::runtime_error(
          fmt::format("map frames: only the known scenarios have a map run, "
                      "not {}",
                      to_string(o.scenario)));
    }
    if (*o.map_frames < 1 || *o.map_frames > 1'000'000) {
      throw std::runtime_error(
          fmt::format("map frames: expected 1 to 1000000 frames, got {}", *o.map_frames));
    }
  }
  if (o.frame_stride < 1 || o.frame_stride > o.frames) {
    throw std::runtime_error(fmt::format("frame stride: expected 1 to {} (the frames), got {}",
                                         o.frames, o.frame_stride));
  }
  if (o.threads < 1) throw std::runtime_error("threads: expected at least 1");
  if (!(o.gps.sigma_m >= 0)) throw std::runtime_error("gps sigma: expected >= 0");
  if (!(o.gps.dropout_rate_per_min >= 0))
    throw std::runtime_error("gps drop-out rate: expected >= 0");
  if (!(o.gps.dropout_mean_s >= 0))
    throw std::runtime_error("gps drop-out duration: expected >= 0");
  if (o.image.noise_sigma < 0 || o.image.blur_sigma_px < 0) {
    throw std::runtime_error("image noise and blur must not be negative");
  }
  if (!(std::abs(o.loc_lateral_offset_m) <= 2.0))
    throw std::runtime_error("loc lateral offset: expected a value in [-2, 2] m");
  if (!(o.loc_speed_scale >= 0.25 && o.loc_speed_scale <= 2.0))
    throw std::runtime_error("loc speed scale: expected a value in [0.25, 2]");
  const double imu_period_ns = 1e9 / o.imu.rate_hz;
  if (!(o.imu.rate_hz > 0) ||
      std::abs(static_cast<double>(kCameraPeriodNs) / imu_period_ns -
               std::round(static_cast<double>(kCameraPeriodNs) / imu_period_ns)) > 1e-9) {
    throw std::runtime_error("imu rate: must be a multiple of the 20 Hz camera rate");
  }
}

std::string describe(const GenerateOptions& o, const StereoRig& rig,
                     const std::vector<RunSummary>& runs) {
  std::string y = "# edx gen: synthetic dataset in the EuRoC ASL layout (see docs/DATASETS.md)\n";
  y += fmt::format("scenario: {}\n", to_string(o.scenario));
  y += fmt::format("world: {}\n", is_outdoor(o.scenario) ? "street" : "warehouse");
  y += fmt::format("seed: {}\n", o.seed);
  y += fmt::format("frames_per_run: {}\n", o.frames);
  if (o.map_frames) y += fmt::format("map_frames: {}\n", *o.map_frames);
  if (o.frame_stride != 1) y += fmt::format("frame_stride: {}\n", o.frame_stride);
  y += fmt::format("rig: {}\n", to_string(rig.kind));
  y += fmt::format("resolution: [{}, {}]\n", rig.width, rig.height);
  y += fmt::format("baseline_m: {}\n", rig.baseline_m);
  y += fmt::format("camera_rate_hz: {}\n", kCameraRateHz);
  y += fmt::format("imu_rate_hz: {}\n", o.imu.rate_hz);
  y += fmt::format("imu_noise_free: {}\n", o.imu.noise_free);
  y += fmt::format("image_noise: {}\n", o.image.enabled);
  y += fmt::format("gps: {}\n", is_outdoor(o.scenario));
  if (is_outdoor(o.scenario)) {
    y += fmt::format(
        "gps_rate_hz: {}\ngps_sigma_m: {}\ngps_dropout_rate_per_min: {}\n"
        "gps_dropout_mean_s: {}\n",
        o.gps.rate_hz, o.gps.sigma_m, o.gps.dropout_rate_per_min, o.gps.dropout_mean_s);
  }
  if (has_map_run(o.scenario)) {
    y += fmt::format("loc_route: {}\n", to_string(o.loc_route));
    if (o.loc_route == RevisitMode::kRetraverse) {
      y += fmt::format("loc_lateral_offset_m: {}\nloc_speed_scale: {}\n", o.loc_lateral_offset_m,
                       o.loc_speed_scale);
    }
  }
  y += "runs:\n";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunSummary& r = runs[i];
    y += fmt::format("  - name: {}\n", r.name.empty() ? "single" : r.name);
    y += fmt::format("    path: {}\n", r.name.empty() ? "mav0" : r.name + "/mav0");
    y += fmt::format("    start_ns: {}\n",
                     kStartTimeNs + static_cast<std::int64_t>(i) * kLocalizationDelayNs);
    y += fmt::format("    frames: {}\n", r.frames);
    y += fmt::format("    duration_s: {:.3f}\n", r.duration_s);
    y += fmt::format("    path_length_m: {:.3f}\n", r.path_length_m);
    y += fmt::format("    gps_fixes: {}\n", r.gps_fixes);
    y += "    route: [";
    for (std::size_t k = 0; k < r.route.size(); ++k)
      y += (k ? ", " : "") + std::to_string(r.route[k]);
    y += "]\n";
  }
  return y;
}

}  // namespace

GenerateSummary generate_dataset(const GenerateOptions& options, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  validate(options);
  fs::path out = options.out.lexically_normal();
  if (out.has_filename() == false && out.has_parent_path()) out = out.parent_path();
  check_output(out, options.force);

  GenerateSummary summary;
  summary.rig = resolve_rig(options);
  const StereoRig& rig = summary.rig;

  const fs::path parent = out.has_parent_path() ? out.parent_path() : fs::path(".");
  // fmt rather than "." + string: GCC 12 reports a false -Wrestrict on the inlined operator+.
  const fs::path tmp = parent / fmt::format(".{}.edx-gen-tmp", out.filename().string());
  std::error_code ec;
  fs::remove_all(tmp, ec);
  if (!fs::create_directories(tmp, ec) || ec) {
    throw std::runtime_error(tmp.string() + ": cannot create temporary directory: " + ec.message());
  }
  TempDirGuard guard(tmp);

  const bool outdoor = is_outdoor(options.scenario);
  const Scene scene = build_scene(options.scenario, options.seed);
  const std::vector<Eigen::Vector3d> body_points = {rig.T_body_left.translation(),
                                                    rig.T_body_right().translation()};
  const std::int64_t imu_period_ns = std::llround(1e9 / options.imu.rate_hz);
  const std::vector<std::string> run_names = has_map_run(options.scenario)
                                                 ? std::vector<std::string>{"map", "loc"}
                                                 : std::vector<std::string>{""};

  Revisit revisit;
  revisit.mode = options.loc_route;
  revisit.lateral_offset_m = options.loc_lateral_offset_m;
  revisit.speed_scale = options.loc_speed_scale;
  double render_seconds = 0;
  for (std::size_t r = 0; r < run_names.size(); ++r) {
    const std::string& name = run_names[r];
    const int frames = r == 0 && options.map_frames ? *options.map_frames : options.frames;
    const std::int64_t duration_ns = static_cast<std::int64_t>(frames - 1) * kCameraPeriodNs;
    const double duration_s = static_cast<double>(duration_ns) * 1e-9;
    const std::uint64_t run_seed = derive_seed(options.seed, "run", r);
    const PlannedTrajectory planned = plan_trajectory(scene, std::max(duration_s, 0.1), run_seed,
                                                      body_points, r == 0 ? nullptr : &revisit);
    if (r == 0) revisit.route = planned.route;
    const Trajectory& traj = planned.trajectory;
    const std::int64_t t0 = kStartTimeNs + static_cast<std::int64_t>(r) * kLocalizationDelayNs;

    const fs::path run_dir = name.empty() ? tmp : tmp / name;
    EurocWriter writer(
        run_dir / "mav0", rig, kCameraRateHz / options.frame_stride,
        fmt::format("edx synthetic {} ({}{}), {} rig, seed {}", to_string(options.scenario),
                    outdoor ? "street" : "warehouse", name.empty() ? "" : ", " + name + " run",
                    to_string(rig.kind), options.seed));
    StereoCamera camera(scene.world, rig, options.image, run_seed, options.threads);
    for (int k = 0; k < frames; ++k) {
      if (k % options.frame_stride != 0) {
        camera.skip();
        if (progress) progress(name, k + 1, frames);
        continue;
      }
      const std::int64_t offset_ns = static_cast<std::int64_t>(k) * kCameraPeriodNs;
      const BodyState state = traj.at(static_cast<double>(offset_ns) * 1e-9);
      const auto t_render = std::chrono::steady_clock::now();
      const StereoImages images = camera.capture(state.T_world_body());
      render_seconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t_render).count();
      writer.add_frame(t0 + offset_ns, images.left, images.right);
      if (progress) progress(name, k + 1, frames);
    }
    const std::size_t imu_count = static_cast<std::size_t>(duration_ns / imu_period_ns) + 1;
    const InertialTrack inertial = simulate_inertial(traj, t0, imu_count, options.imu, run_seed);
    writer.write_imu(inertial.imu, options.imu);
    writer.write_ground_truth(inertial.ground_truth);
    RunSummary run;
    if (outdoor) {
      const auto fixes = simulate_gps(traj, t0, duration_s, options.gps, run_seed);
      writer.write_gps(fixes, options.gps);
      run.gps_fixes = fixes.size();
    }
    writer.finish();

    run.name = name;
    run.mav0 = (name.empty() ? out : out / name) / "mav0";
    run.frames = (frames + options.frame_stride - 1) / options.frame_stride;  // written
    run.imu_samples = inertial.imu.size();
    run.duration_s = duration_s;
    for (std::size_t i = 1; i < inertial.ground_truth.size(); ++i) {
      run.path_length_m +=
          (inertial.ground_truth[i].position - inertial.ground_truth[i - 1].position).norm();
    }
    run.mean_speed_m_s = duration_s > 0 ? run.path_length_m / duration_s : 0.0;
    run.route = planned.route;
    summary.runs.push_back(std::move(run));
  }
  write_text_file(tmp / "edx_gen.yaml", describe(options, rig, summary.runs));

  // Publish: replace the (empty, or forced) output directory by the finished one.
  if (fs::exists(out)) {
    fs::remove_all(out, ec);
    if (ec) throw std::runtime_error(out.string() + ": cannot remove: " + ec.message());
  }
  fs::rename(tmp, out, ec);
  if (ec)
    throw std::runtime_error(out.string() +
                             ": cannot move finished dataset into place: " + ec.message());
  guard.release();
  summary.render_seconds = render_seconds;
  summary.total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace edx::synthetic
