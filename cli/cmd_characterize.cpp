// `edx characterize`: the paper's algorithm characterization (Sec. III; issue 42): every
// applicable backend on each of the four synthetic scenarios, several unseen seeds, its ATE and
// its frame rate on a platform's CPU-only baseline, beside the paper's. Logic:
// workloads/modes/characterization.hpp (the runs), reports/characterization.hpp (the study).
#include <fmt/core.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "arch/platform/platform.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "common/atomic_file.hpp"
#include "common/resources.hpp"
#include "reports/characterization.hpp"
#include "reports/paper_check.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/modes/characterization.hpp"

namespace edx::cli {
namespace {

namespace fs = std::filesystem;

struct CharacterizeArguments {
  int seeds = 3;
  int frames = 400;
  std::string resolution = "1280x720";
  std::string precision = "fp64";
  std::vector<std::string> scenarios;
  std::string platform;
  std::string out;
  std::string data;
  int jobs = 0;
  bool force = false;
  bool json = false;
};

void run(const CharacterizeArguments& args) {
  const arch::Platform platform = arch::Platform::load(
      args.platform.empty() ? common::find_resource("configs/edx_car.yaml").string()
                            : args.platform);
  const reports::PaperCharacterization paper =
      reports::PaperCharacterization::load(reports::default_targets_path());
  const cv::Size size = datasets::parse_resolution(args.resolution);
  modes::CharacterizationOptions options;
  options.seeds = args.seeds;
  options.frames = args.frames;
  options.resolution = {size.width, size.height};
  options.precision = trace::parse_precision(args.precision);
  for (const std::string& s : args.scenarios) {
    options.scenarios.push_back(synthetic::parse_scenario(s));
  }
  // The frame rates simulate the traces on the platform: it must compute at their precision
  // (checked here, before any tracing).
  if (platform.backend->precision() != options.precision) {
    throw std::runtime_error(fmt::format(
        "--precision {}: platform {} computes in {} (backend.precision); give --platform a "
        "platform of backend.precision: {}",
        args.precision, platform.name, trace::to_string(platform.backend->precision()),
        args.precision));
  }
  const fs::path out(args.out);
  if (fs::exists(out) && !fs::is_directory(out)) {
    throw std::runtime_error(fmt::format("{}: exists and is not a folder (--out)", out.string()));
  }
  options.trace_dir = out / "traces";
  options.data_dir = args.data.empty() ? out / "data" : fs::path(args.data);
  options.overwrite = args.force;
  options.threads = jobs_or_cores(args.jobs);
  options.validate();
  ProgressBar bar("characterize");
  const std::vector<modes::CharacterizationRun> runs = modes::run_characterization(
      options,
      [&bar](std::string_view run, std::string_view stage, std::size_t done, std::size_t total) {
        bar.update(done, total, "frames", fmt::format("{} {}", run, stage));
      });
  const reports::CharacterizationStudy study =
      reports::study_characterization(runs, platform, paper);
  const std::string json = study.to_json().dump(2) + "\n";
  common::write_file_atomically(out / "characterization.json", json);
  const std::string text = reports::format_characterization(study);
  common::write_file_atomically(out / "characterization.txt", text);
  fmt::print("{}", args.json ? json : text);
}

}  // namespace

void add_characterize_command(CLI::App& app) {
  auto args = std::make_shared<CharacterizeArguments>();
  CLI::App* cmd = app.add_subcommand(
      "characterize",
      "The paper's algorithm characterization (Sec. III): each backend on each synthetic "
      "scenario over unseen seeds, its ATE and its frame rate on a platform's CPU baseline, "
      "beside the paper's (docs/CHARACTERIZATION.md)");
  cmd->add_option("--seeds", args->seeds, "Seeds per run, from 1001 on (unseen by any tuning)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Frames of each measured run (and of a mapping run)")
      ->check(CLI::Range(8, 100000))
      ->capture_default_str();
  cmd->add_option("--resolution", args->resolution, "Rendering resolution WxH")
      ->check(resolution_validator())
      ->capture_default_str();
  cmd->add_option("--scenario", args->scenarios,
                  "Run only this scenario (repeatable; default all four)")
      ->check(
          CLI::IsMember({"indoor_unknown", "indoor_known", "outdoor_unknown", "outdoor_known"}));
  cmd->add_option("--precision", args->precision,
                  "Arithmetic of the backends' offloadable kernels, fp64 or fp32 (edx trace "
                  "--precision); the platform's backend.precision must match")
      ->check(CLI::IsMember({"fp64", "fp32"}))
      ->capture_default_str();
  cmd->add_option(
      "--platform", args->platform,
      "Platform whose CPU baseline the frame rates are on (default configs/edx_car.yaml)");
  cmd->add_option("--out", args->out,
                  "Output folder: characterization.json and .txt, the runs' traces (traces/), "
                  "the generated worlds (data/); a run already traced there is reused")
      ->required();
  cmd->add_option("--data", args->data, "Folder of the generated worlds (default OUT/data)");
  cmd->add_option("-j,--jobs", args->jobs,
                  "Runs traced at once (each scenario's runs of a seed one after another); the "
                  "runs and figures do not depend on it (default: all cores)")
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--force", args->force, "Trace every run again");
  cmd->add_flag("--json", args->json, "Print the study as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
