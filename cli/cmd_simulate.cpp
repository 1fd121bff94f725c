// `edx simulate`: runs a trace through a platform model (the whole system against its CPU-only
// baseline, docs/MODEL.md "System") and prints its figures; --out adds the run to a results
// database. Logic: arch/system.
#include <fmt/core.h>

#include <optional>
#include <string>

#include "arch/platform/platform.hpp"
#include "arch/results/results_db.hpp"
#include "arch/system/frontend_study.hpp"
#include "arch/system/result_rows.hpp"
#include "arch/system/system_model.hpp"
#include "cli/commands.hpp"
#include "reports/metrics.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::cli {
namespace {

struct SimulateArguments {
  std::string config;
  std::string trace;
  std::string timeline;
  std::string out;
  std::size_t timeline_first = 0;
  std::size_t timeline_frames = 10;
  std::string model = "des";
  int jobs = 0;
  bool json = false;
  SeedOptions seeds;
};

/// --workload --seeds: the workload's trace of each seed simulated (each run added to --out);
/// every figure of the runs' summaries as its mean and 95 % interval.
void run_seeds(const SimulateArguments& args) {
  const arch::Platform platform = arch::Platform::load(args.config);
  arch::SystemSimOptions options;
  options.model = arch::parse_system_model(args.model);
  options.threads = jobs_or_cores(args.jobs);
  std::vector<nlohmann::json> trees;
  nlohmann::json runs = nlohmann::json::array();
  const nlohmann::json workload = args.seeds.workload_json();
  const std::string group = args.seeds.group();
  for (const arch::SeedTrace& s : args.seeds.traces(options.threads)) {
    const trace::TraceReader reader(s.trace.string());
    const arch::SystemResult result = arch::simulate_system(
        platform, reader.read_all(), reader.meta(), s.trace.string(), options);
    if (!args.out.empty()) {
      results::RunRows rows = arch::result_rows(result);
      rows.seed_runs.push_back(
          {rows.run.run_id, group, workload, static_cast<std::int64_t>(s.seed)});
      arch::write_results(args.out, rows);
    }
    trees.push_back({{"system", result.to_json()}});
    runs.push_back({{"seed", s.seed},
                    {"trace", s.trace.string()},
                    {"run_id", results::run_id_of(result.config_hash, result.trace_hash)}});
  }
  const auto figures = reports::figures_over_runs(trees);
  if (args.json) {
    nlohmann::json out = {{"runs", runs}, {"figures", nlohmann::json::object()}};
    for (const auto& [path, i] : figures) {
      out["figures"][path] = {{"mean", i.mean}, {"low", i.low}, {"high", i.high}, {"n", i.n}};
    }
    fmt::print("{}\n", out.dump(2));
    return;
  }
  for (const nlohmann::json& r : runs) {
    fmt::print("seed {:<6} {} (run {})\n", r["seed"].get<std::uint64_t>(),
               r["trace"].get<std::string>(), r["run_id"].get<std::string>());
  }
  fmt::print("\n{}", reports::format_figures_over_runs(figures, /*headline_only=*/true));
  fmt::print("(--json: all {} figures)\n", figures.size());
  if (!args.out.empty()) fmt::print("results    {} ({} runs)\n", args.out, runs.size());
}

void run(const SimulateArguments& args) {
  if (args.seeds.given()) return run_seeds(args);
  const arch::Platform platform = arch::Platform::load(args.config);
  const trace::TraceReader reader(args.trace);
  const std::vector<trace::FrameTrace> frames = reader.read_all();
  arch::SystemSimOptions options;
  options.model = arch::parse_system_model(args.model);
  options.threads = jobs_or_cores(args.jobs);
  if (!args.timeline.empty()) {
    options.timeline = args.timeline;
    options.timeline_first = args.timeline_first;
    options.timeline_count = args.timeline_frames;
  }
  const arch::SystemResult result =
      arch::simulate_system(platform, frames, reader.meta(), args.trace, options);
  if (!args.out.empty()) arch::write_results(args.out, arch::result_rows(result));
  if (args.json) {
    fmt::print(
        "{}\n",
        nlohmann::json{{"frontend", result.frontend.to_json()}, {"system", result.to_json()}}.dump(
            2));
  } else {
    fmt::print("{}", arch::format_frontend_study(result.frontend));
    fmt::print("{}", arch::format_system_result(result));
    if (!args.timeline.empty()) fmt::print("timeline   {}\n", args.timeline);
    if (!args.out.empty())
      fmt::print("results    {} (run {}-{})\n", args.out, result.config_hash, result.trace_hash);
  }
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArguments>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run a trace through a platform model (configs/*.yaml) and print its figures");
  cmd->add_option("--config", args->config, "Platform description (YAML)")->required();
  auto* trace = cmd->add_option("--trace", args->trace, "Trace database written by edx trace");
  add_seed_options(*cmd, args->seeds, trace);
  cmd->add_option("--out", args->out,
                  "Results database (SQLite) to add the run to; the same config and trace "
                  "replace their earlier run");
  cmd->add_option("--timeline", args->timeline,
                  "Write a Perfetto timeline (Chrome trace JSON) of the whole system's streamed "
                  "run (model des; the pipelined frontend with --model analytical)");
  cmd->add_option("--timeline-first", args->timeline_first, "First frame of the timeline");
  cmd->add_option("--timeline-frames", args->timeline_frames, "Frames in the timeline")
      ->check(positive_number());
  cmd->add_option("--model", args->model,
                  "des: the whole-system discrete-event simulation; analytical: the closed-form "
                  "model it reduces to without contention (cross-check)")
      ->check(CLI::IsMember({"des", "analytical"}))
      ->capture_default_str();
  cmd->add_option("-j,--jobs", args->jobs,
                  "Threads for a run's independent parts (the frontend study's, the four DES "
                  "runs) and for the seeds' tracing (--seeds: the missing seeds traced at once); "
                  "the figures do not depend on it (default: all cores)")
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--json", args->json, "Print the figures as JSON (only JSON on stdout)");
  cmd->callback([args] {
    if (args->trace.empty() && !args->seeds.given()) {
      throw CLI::RequiredError("--trace (or --workload with --seeds and --trace-store)");
    }
    if (args->seeds.given() && !args->timeline.empty()) {
      throw CLI::ValidationError("--timeline", "is for one trace, not with --seeds");
    }
    run(*args);
  });
}

}  // namespace edx::cli
