// `edx trace`: runs the localization pipeline (the stereo frontend and a backend) over a dataset
// and writes a trace database (docs/TRACE.md); with --mix, over a mixed sequence of synthetic
// scenarios with the mode switch choosing the backend (docs/MODES.md). Logic: workloads/modes.
#include <fmt/core.h>

#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/modes/backend_registry.hpp"
#include "workloads/modes/mix_runner.hpp"
#include "workloads/modes/trace_runner.hpp"

namespace edx::cli {
namespace {

struct TraceArguments {
  std::string dataset;
  std::string format;
  std::size_t frames = 0;
  std::string resolution;
  std::string kitti_sequence;
  std::string scenario;
  std::string out;
  std::string backend = "none";
  std::string save_map;
  std::string map;
  std::string vocab;
  int features = frontend::FrontendOptions{}.features_per_image;
  bool force = false;
  bool json = false;
  bool parallel = false;
  std::string mix;
  std::string data;
  std::uint64_t seed = 1;
  int map_frames = 0;  ///< 0: the mix's default
  std::string precision = "fp64";
};

/// `--mix NAME`: the mixed sequence through the mode switch.
void run_mix(const TraceArguments& args) {
  const cv::Size size =
      datasets::parse_resolution(args.resolution.empty() ? "640x480" : args.resolution);
  modes::MixRunOptions options;
  options.plan = modes::make_mix(
      args.mix, args.frames > 0 ? static_cast<int>(args.frames) : 400, {size.width, size.height},
      args.seed, args.map_frames > 0 ? std::optional<int>(args.map_frames) : std::nullopt);
  options.data_dir = args.data.empty() ? std::filesystem::path(args.out + ".data")
                                       : std::filesystem::path(args.data);
  options.out = args.out;
  options.overwrite = args.force;
  options.frontend.features_per_image = args.features;
  options.frontend.parallel_images = args.parallel;
  options.vocabulary = args.vocab;
  options.precision = trace::parse_precision(args.precision);

  ProgressBar bar("trace");
  const modes::MixRunSummary summary =
      modes::run_mix(options, [&bar](std::string_view stage, std::size_t done, std::size_t total) {
        bar.update(done, total, "frames", stage);
      });
  if (args.json) {
    fmt::print("{}\n", modes::to_json(summary).dump(2));
  } else {
    fmt::print("{}", modes::format_summary(summary));
  }
}

void run(const TraceArguments& args) {
  if (!args.mix.empty()) return run_mix(args);
  modes::TraceRunOptions options;
  options.dataset_path = args.dataset;
  options.format = datasets::parse_dataset_format(args.format);
  if (!args.resolution.empty())
    options.dataset.resize = datasets::parse_resolution(args.resolution);
  options.dataset.kitti_sequence = args.kitti_sequence;
  if (args.frames > 0) options.max_frames = args.frames;
  if (!args.scenario.empty()) options.scenario = trace::parse_scenario(args.scenario);
  options.out = args.out;
  options.overwrite = args.force;
  options.frontend.features_per_image = args.features;
  options.frontend.parallel_images = args.parallel;
  modes::BackendSettings settings;
  if (!args.map.empty()) settings.map = args.map;
  if (!args.vocab.empty()) settings.vocabulary = args.vocab;
  settings.precision = options.precision = trace::parse_precision(args.precision);
  options.make_backend = modes::backend_factory(args.backend, settings);
  if (!args.save_map.empty()) options.map_out = args.save_map;

  ProgressBar bar("trace");
  const modes::TraceRunSummary summary = modes::run_trace(
      options, [&bar](std::size_t done, std::size_t total) { bar.update(done, total, "frames"); });
  if (args.json) {
    fmt::print("{}\n", modes::to_json(summary).dump(2));
  } else {
    fmt::print("{}", modes::format_summary(summary));
  }
}

}  // namespace

void add_trace_command(CLI::App& app) {
  auto args = std::make_shared<TraceArguments>();
  CLI::App* cmd = app.add_subcommand(
      "trace",
      "Run the localization pipeline (stereo frontend) over a dataset and write a trace "
      "database (docs/TRACE.md)");
  CLI::Option* dataset_opt =
      cmd->add_option("--dataset", args->dataset,
                      "Dataset folder: EuRoC (the folder holding mav0/, or mav0/) or a KITTI "
                      "sequence folder (sequences/NN)");
  CLI::Option* format_opt =
      cmd->add_option("--format", args->format, "Dataset format (with --dataset)")
          ->check(CLI::IsMember({"euroc", "kitti"}));
  cmd->add_option("--out", args->out, "Trace database to write")->required();
  cmd->add_option("--frames", args->frames,
                  "Process only the first N frames (with --mix: frames of the whole mix, "
                  "default 400)")
      ->check(positive_number());
  cmd->add_option("--resolution", args->resolution,
                  "Resize the rectified frames to WxH (e.g. 640x480; with --mix: the resolution "
                  "the worlds are rendered at, default 640x480)")
      ->check(resolution_validator());
  CLI::Option* kitti_opt =
      cmd->add_option("--kitti-sequence", args->kitti_sequence,
                      "KITTI sequence id (e.g. 01) when --dataset is the KITTI root");
  CLI::Option* scenario_opt =
      cmd->add_option("--scenario", args->scenario,
                      "Scenario recorded on the frames (default: outdoor_unknown for KITTI and "
                      "data with GPS, else indoor_unknown)")
          ->check(CLI::IsMember(
              {"indoor_unknown", "indoor_known", "outdoor_unknown", "outdoor_known"}));
  CLI::Option* backend_opt = cmd->add_option("--backend", args->backend,
                                             "Backend run on every frame (none: frontend only)")
                                 ->check(CLI::IsMember(modes::backend_names()))
                                 ->capture_default_str();
  CLI::Option* save_map_opt = cmd->add_option(
      "--save-map", args->save_map,
      "Save the map the backend built (slam only) to this file (JSON, docs/SLAM.md)");
  CLI::Option* map_opt = cmd->add_option(
      "--map", args->map,
      "Map to localize in (registration only; written by --backend slam --save-map)");
  cmd->add_option("--vocab", args->vocab,
                  "BoW vocabulary for the keyframe database (registration only; edx vocab)");
  cmd->add_option("--features", args->features, "Keypoint budget per image")
      ->check(positive_number());
  cmd->add_option("--precision", args->precision,
                  "Arithmetic of the backend's offloadable kernels (Kalman gain and covariance "
                  "update, marginalization, projection): fp64 or fp32 (docs/TRACE.md, meta "
                  "precision)")
      ->check(CLI::IsMember({"fp64", "fp32"}))
      ->capture_default_str();
  cmd->add_flag("--parallel", args->parallel,
                "Run tracking and feature extraction on parallel threads (faster; host times stay "
                "CPU time of the work, docs/TRACE.md)");
  CLI::Option* mix_opt =
      cmd->add_option(
             "--mix", args->mix,
             "Run a mixed sequence of synthetic scenarios instead of --dataset, the mode "
             "switch choosing the backend per frame (paper: 50% outdoor, 25% indoor without "
             "a map, 25% indoor with a map; or one scenario: outdoor, indoor_unknown, "
             "indoor_known; docs/MODES.md)")
          ->check(CLI::IsMember(modes::mix_names()));
  cmd->add_option("--data", args->data,
                  "With --mix: folder of the generated worlds, saved maps and vocabulary, reused "
                  "across runs (default: OUT.data)");
  cmd->add_option("--seed", args->seed, "With --mix: seed of the synthetic worlds")
      ->capture_default_str();
  CLI::Option* map_frames_opt =
      cmd->add_option("--map-frames", args->map_frames,
                      "With --mix paper or indoor_known: frames of the mapping run, the size of "
                      "the map later frames register in (default: a quarter, or half, of --frames)")
          ->check(CLI::Range(2, 1000000));
  cmd->add_flag("--force", args->force, "Overwrite an existing output file");
  cmd->add_flag("--json", args->json, "Print the summary as JSON (only JSON on stdout)");
  // Either a dataset (with its format) or a mix, which generates its data and lets the mode
  // switch pick the backend.
  dataset_opt->needs(format_opt);
  format_opt->needs(dataset_opt);
  mix_opt->excludes(dataset_opt, format_opt, kitti_opt, scenario_opt, backend_opt, save_map_opt,
                    map_opt);
  map_frames_opt->needs(mix_opt);
  cmd->callback([args, dataset_opt, mix_opt] {
    if (dataset_opt->count() == 0 && mix_opt->count() == 0) {
      throw CLI::RequiredError("--dataset or --mix");
    }
    run(*args);
  });
}

}  // namespace edx::cli
