// `edx trace`: runs the localization pipeline (the stereo frontend and a backend) over a dataset
// and writes a trace database (docs/TRACE.md). Logic: workloads/modes/trace_runner.
#include <fmt/core.h>

#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/modes/backend_registry.hpp"
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
  int features = frontend::FrontendOptions{}.features_per_image;
  bool force = false;
  bool json = false;
  bool parallel = false;
};

void run(const TraceArguments& args) {
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
  options.make_backend = modes::backend_factory(args.backend);
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
  cmd->add_option("--dataset", args->dataset,
                  "Dataset folder: EuRoC (the folder holding mav0/, or mav0/) or a KITTI "
                  "sequence folder (sequences/NN)")
      ->required();
  cmd->add_option("--format", args->format, "Dataset format")
      ->required()
      ->check(CLI::IsMember({"euroc", "kitti"}));
  cmd->add_option("--out", args->out, "Trace database to write")->required();
  cmd->add_option("--frames", args->frames, "Process only the first N frames")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--resolution", args->resolution,
                  "Resize the rectified frames to WxH (e.g. 640x480)")
      ->check(CLI::Validator(
          [](std::string& text) {
            try {
              datasets::parse_resolution(text);
            } catch (const std::exception& e) {
              return std::string(e.what());
            }
            return std::string();
          },
          "WxH"));
  cmd->add_option("--kitti-sequence", args->kitti_sequence,
                  "KITTI sequence id (e.g. 01) when --dataset is the KITTI root");
  cmd->add_option("--scenario", args->scenario,
                  "Scenario recorded on the frames (default: outdoor_unknown for KITTI and "
                  "data with GPS, else indoor_unknown)")
      ->check(
          CLI::IsMember({"indoor_unknown", "indoor_known", "outdoor_unknown", "outdoor_known"}));
  cmd->add_option("--backend", args->backend, "Backend run on every frame (none: frontend only)")
      ->check(CLI::IsMember(modes::backend_names()))
      ->capture_default_str();
  cmd->add_option("--save-map", args->save_map,
                  "Save the map the backend built (slam only) to this file (JSON, docs/SLAM.md)");
  cmd->add_option("--features", args->features, "Keypoint budget per image")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--parallel", args->parallel,
                "Run tracking and feature extraction on parallel threads (faster; per-task host "
                "times then include waiting for a core)");
  cmd->add_flag("--force", args->force, "Overwrite an existing output file");
  cmd->add_flag("--json", args->json, "Print the summary as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
