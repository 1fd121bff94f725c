// `edx gen`: renders a synthetic dataset of one of the four scenarios in the EuRoC layout.
// Thin: parses arguments, calls edx::synthetic::generate_dataset, reports progress on stderr.
#include <fmt/core.h>

#include <memory>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "workloads/datasets/synthetic/generator.hpp"

namespace edx::cli {

namespace {

struct GenArgs {
  std::string scenario;
  int frames = 200;
  int map_frames = 0;  ///< 0: as --frames
  std::string resolution;
  std::string rig;
  std::uint64_t seed = 1;
  std::string out;
  bool force = false;
  int threads = 2;
  double gps_sigma = 0.5;
  double gps_dropout_rate = 1.0;
  double gps_dropout_duration = 3.0;
  bool imu_noise_free = false;
  bool no_image_noise = false;
  std::string loc_route = "retraverse";
};

void run_gen(const GenArgs& a) {
  synthetic::GenerateOptions o;
  o.scenario = synthetic::parse_scenario(a.scenario);
  o.frames = a.frames;
  if (a.map_frames != 0) o.map_frames = a.map_frames;
  if (!a.resolution.empty()) o.resolution = synthetic::parse_resolution(a.resolution);
  if (!a.rig.empty()) o.rig = synthetic::parse_rig(a.rig);
  o.seed = a.seed;
  o.out = a.out;
  o.force = a.force;
  o.threads = a.threads;
  o.gps.sigma_m = a.gps_sigma;
  o.gps.dropout_rate_per_min = a.gps_dropout_rate;
  o.gps.dropout_mean_s = a.gps_dropout_duration;
  o.imu.noise_free = a.imu_noise_free;
  o.image.enabled = !a.no_image_noise;
  o.loc_route = synthetic::parse_loc_route(a.loc_route);
  ProgressBar bar("gen");
  const synthetic::GenerateSummary s =
      synthetic::generate_dataset(o, [&bar](std::string_view run, int done, int total) {
        bar.update(static_cast<std::size_t>(done), static_cast<std::size_t>(total), "frames",
                   run.empty() ? std::string() : std::string(run) + " run");
      });
  fmt::print("wrote {}: {}, {} rig {}x{} (baseline {} m), seed {}\n", a.out, a.scenario,
             synthetic::to_string(s.rig.kind), s.rig.width, s.rig.height, s.rig.baseline_m, a.seed);
  for (const auto& run : s.runs) {
    fmt::print(
        "  {}: {} frames, {:.1f} s, {:.1f} m at {:.2f} m/s mean, {} IMU samples, {} GPS fixes\n",
        run.mav0.string(), run.frames, run.duration_s, run.path_length_m, run.mean_speed_m_s,
        run.imu_samples, run.gps_fixes);
  }
  int images = 0;
  for (const auto& run : s.runs) images += 2 * run.frames;
  fmt::print("  rendering {:.1f} images/s; total {:.1f} s\n",
             s.render_seconds > 0 ? images / s.render_seconds : 0.0, s.total_seconds);
}

}  // namespace

void add_gen_command(CLI::App& app) {
  auto args = std::make_shared<GenArgs>();
  CLI::App* cmd = app.add_subcommand(
      "gen",
      "Render a synthetic stereo/IMU/GPS dataset in the EuRoC layout (DIR/mav0, or DIR/map/mav0 "
      "and DIR/loc/mav0 for the known scenarios)");
  cmd->add_option("--scenario", args->scenario,
                  "indoor_unknown | indoor_known | outdoor_unknown | outdoor_known")
      ->required();
  cmd->add_option("--out", args->out, "output directory DIR (must not exist or be empty)")
      ->required();
  cmd->add_option("--frames", args->frames, "stereo frames per run (20 Hz)")->capture_default_str();
  cmd->add_option("--map-frames", args->map_frames,
                  "known scenarios: frames of the map run (default: --frames); a longer map run "
                  "maps more than the loc run visits")
      ->check(CLI::Range(1, 1'000'000));
  cmd->add_option("--resolution", args->resolution,
                  "WIDTHxHEIGHT (default: the rig's, 752x480 euroc, 1280x720 car)");
  cmd->add_option("--rig", args->rig,
                  "euroc | car (default: by resolution, else euroc indoors, car outdoors)");
  cmd->add_option("--seed", args->seed, "random seed (same seed, same bytes)")
      ->capture_default_str();
  cmd->add_flag("--force", args->force, "replace DIR if it exists and is not empty");
  cmd->add_option("--threads", args->threads, "render threads")->capture_default_str();
  cmd->add_option("--gps-sigma", args->gps_sigma, "GPS noise per axis, m (outdoor)")
      ->capture_default_str();
  cmd->add_option("--gps-dropout-rate", args->gps_dropout_rate,
                  "GPS drop-outs starting per minute (outdoor)")
      ->capture_default_str();
  cmd->add_option("--gps-dropout-duration", args->gps_dropout_duration,
                  "mean GPS drop-out duration, s (outdoor)")
      ->capture_default_str();
  cmd->add_flag("--imu-noise-free", args->imu_noise_free, "ideal IMU: no noise, zero biases");
  cmd->add_flag("--no-image-noise", args->no_image_noise,
                "ideal images: no exposure change, blur or noise");
  cmd->add_option("--loc-route", args->loc_route,
                  "known scenarios: the loc run re-traverses the map route (retraverse) or "
                  "leaves it (diverge)")
      ->check(CLI::IsMember({"retraverse", "diverge"}))
      ->capture_default_str();
  cmd->callback([args] { run_gen(*args); });
}

}  // namespace edx::cli
