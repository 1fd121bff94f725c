// `edx simulate`: runs a trace through a platform model and prints its figures (now: the
// frontend accelerator against the CPU baseline). Logic: arch/system.
#include <fmt/core.h>

#include <optional>
#include <string>

#include "arch/system/frontend_study.hpp"
#include "arch/system/platform.hpp"
#include "cli/commands.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::cli {
namespace {

struct SimulateArguments {
  std::string config;
  std::string trace;
  std::string timeline;
  std::size_t timeline_first = 0;
  std::size_t timeline_frames = 10;
  bool json = false;
};

void run(const SimulateArguments& args) {
  const arch::Platform platform = arch::Platform::load(args.config);
  const trace::TraceReader reader(args.trace);
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  arch::FrontendSimOptions timeline;
  if (!args.timeline.empty()) {
    timeline.timeline = args.timeline;
    timeline.timeline_first = args.timeline_first;
    timeline.timeline_count = args.timeline_frames;
  }
  const arch::FrontendStudy study =
      arch::study_frontend(platform, frames, reader.meta().at("resolution"), timeline);
  if (args.json) {
    fmt::print("{}\n", nlohmann::json{{"frontend", study.to_json()}}.dump(2));
  } else {
    fmt::print("{}", arch::format_frontend_study(study));
    if (!args.timeline.empty()) fmt::print("timeline   {}\n", args.timeline);
  }
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArguments>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run a trace through a platform model (configs/*.yaml) and print its figures");
  cmd->add_option("--config", args->config, "Platform description (YAML)")->required();
  cmd->add_option("--trace", args->trace, "Trace database written by edx trace")->required();
  cmd->add_option("--timeline", args->timeline,
                  "Write a Perfetto timeline (Chrome trace JSON) of the pipelined frontend");
  cmd->add_option("--timeline-first", args->timeline_first, "First frame of the timeline");
  cmd->add_option("--timeline-frames", args->timeline_frames, "Frames in the timeline")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--json", args->json, "Print the figures as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
