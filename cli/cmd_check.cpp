// `edx check`: the paper's Edx-Car figures (reports/paper_targets.yaml) against a simulated run,
// read from a results database or simulated here from a config and a trace. Prints paper,
// simulated, error and verdict per target; exits 1 when any target misses or is not found (n/a
// rows, figures of modes the run has no frames of, are listed and do not count).
// Logic: reports/paper_check (docs/REPORTS.md).
#include <fmt/core.h>

#include <filesystem>
#include <string>

#include "arch/platform/platform.hpp"
#include "cli/commands.hpp"
#include "common/yaml_fields.hpp"
#include "reports/characterization.hpp"
#include "reports/metrics.hpp"
#include "reports/paper_check.hpp"
#include "reports/results_reader.hpp"
#include "reports/simulated_check.hpp"

namespace edx::cli {
namespace {

struct CheckArguments {
  std::string results;
  std::string config;
  std::string trace;
  std::string run_id;
  std::string targets;
  std::string characterization;
  int jobs = 0;
  bool json = false;
  SeedOptions seeds;
};

/// The characterization study's metrics (--characterization), or null.
nlohmann::json characterization(const CheckArguments& args) {
  if (args.characterization.empty()) return nullptr;
  const std::string text = read_input_file(args.characterization, "characterization file");
  nlohmann::json study;
  try {
    study = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw std::runtime_error(fmt::format(
        "{}: expected JSON (edx characterize's characterization.json)", args.characterization));
  }
  return reports::characterization_metrics(study, args.characterization);
}

void run(const CheckArguments& args) {
  const std::filesystem::path targets_path =
      args.targets.empty() ? reports::default_targets_path() : std::filesystem::path(args.targets);
  const std::vector<reports::PaperTarget> targets = reports::load_targets(targets_path);
  const std::vector<reports::ComparedBaseline> baselines = reports::load_baselines(targets_path);
  const nlohmann::json study = characterization(args);
  std::vector<nlohmann::json> trees;
  std::vector<std::string> run_ids;
  const auto add = [&](nlohmann::json metrics, std::string run_id) {
    if (!study.is_null()) metrics["characterization"] = study;
    trees.push_back(std::move(metrics));
    run_ids.push_back(std::move(run_id));
  };
  if (!args.results.empty()) {
    const reports::ResultsData data = reports::read_results(args.results);
    const reports::RunData& r = reports::pick_run(data, args.run_id);
    nlohmann::json metrics = reports::run_metrics(r);
    reports::add_baseline_metrics(metrics, data, r, baselines);
    add(std::move(metrics), r.run_id);
  } else {
    const arch::Platform platform = arch::Platform::load(args.config);
    if (args.seeds.given()) {
      for (const arch::SeedTrace& s : args.seeds.traces(jobs_or_cores(args.jobs))) {
        reports::SimulatedRun run = reports::simulate_for_check(platform, s.trace, baselines);
        add(std::move(run.metrics), fmt::format("{} (seed {})", run.run_id, s.seed));
      }
    } else {
      reports::SimulatedRun run = reports::simulate_for_check(platform, args.trace, baselines);
      add(std::move(run.metrics), run.run_id);
    }
  }
  const reports::CheckResult check =
      trees.size() == 1 ? reports::check_targets(targets, trees.front(), run_ids.front())
                        : reports::check_targets_over_runs(targets, trees, run_ids);
  if (args.json) {
    fmt::print("{}\n", check.to_json().dump(2));
  } else {
    fmt::print("{}", reports::format_check(check));
  }
  if (!check.all_passed()) throw CLI::RuntimeError(1);
}

}  // namespace

void add_check_command(CLI::App& app) {
  auto args = std::make_shared<CheckArguments>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Compare a run with the paper's Edx-Car figures (reports/paper_targets.yaml)");
  auto* results =
      cmd->add_option("--results", args->results, "Results database written by edx simulate");
  auto* config = cmd->add_option("--config", args->config, "Platform description to simulate");
  auto* trace = cmd->add_option("--trace", args->trace, "Trace database to simulate");
  add_seed_options(*cmd, args->seeds, trace);
  results->excludes(config)->excludes(trace)->excludes("--workload");
  trace->needs(config);
  cmd->add_option("--run", args->run_id, "Run of the results database (default: its only run)")
      ->needs(results);
  cmd->add_option("--targets", args->targets,
                  "Targets file (default: reports/paper_targets.yaml of edx's data folder, see "
                  "edx --version)");
  cmd->add_option("--characterization", args->characterization,
                  "characterization.json of edx characterize: adds its targets (the paper's "
                  "Sec. III orderings and frame rates); without it they are listed as not run");
  cmd->add_option("-j,--jobs", args->jobs,
                  "Threads for the seeds' tracing (--seeds: the missing seeds traced at once); "
                  "the figures do not depend on it (default: all cores)")
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--json", args->json, "Print the table as JSON");
  cmd->callback([args] {
    if (args->results.empty() && args->config.empty()) {
      throw CLI::ValidationError("--results",
                                 "give --results, or --config with --trace or --workload");
    }
    if (!args->config.empty() && args->trace.empty() && !args->seeds.given()) {
      throw CLI::ValidationError("--config", "needs --trace, or --workload with --seeds");
    }
    run(*args);
  });
}

}  // namespace edx::cli
