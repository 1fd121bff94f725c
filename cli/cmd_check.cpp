// `edx check`: the paper's Edx-Car figures (reports/paper_targets.yaml) against a simulated run,
// read from a results database or simulated here from a config and a trace. Prints paper,
// simulated, error and verdict per target; exits 1 when any target misses or is not found (n/a
// rows, figures of modes the run has no frames of, are listed and do not count).
// Logic: reports/paper_check (docs/REPORTS.md).
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "arch/platform/platform.hpp"
#include "arch/results/results_db.hpp"
#include "arch/system/result_rows.hpp"
#include "arch/system/system_model.hpp"
#include "cli/commands.hpp"
#include "common/resources.hpp"
#include "common/yaml_fields.hpp"
#include "reports/characterization.hpp"
#include "reports/metrics.hpp"
#include "reports/paper_check.hpp"
#include "reports/results_reader.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::cli {
namespace {

struct CheckArguments {
  std::string results;
  std::string config;
  std::string trace;
  std::string run_id;
  std::string targets;
  std::string characterization;
  bool json = false;
};

void run(const CheckArguments& args) {
  const std::filesystem::path targets_path =
      args.targets.empty() ? reports::default_targets_path() : std::filesystem::path(args.targets);
  const std::vector<reports::PaperTarget> targets = reports::load_targets(targets_path);
  const std::vector<reports::ComparedBaseline> baselines = reports::load_baselines(targets_path);
  nlohmann::json metrics;
  std::string run_id;
  if (!args.results.empty()) {
    const reports::ResultsData data = reports::read_results(args.results);
    const reports::RunData& r = reports::pick_run(data, args.run_id);
    metrics = reports::run_metrics(r);
    reports::add_baseline_metrics(metrics, data, r, baselines);
    run_id = r.run_id;
  } else {
    // Simulate it and the compared baselines' platforms on the same trace, pass the runs through
    // a scratch results database (one reading path), and add the frontend study, which the
    // results database does not hold.
    const arch::Platform platform = arch::Platform::load(args.config);
    const trace::TraceReader reader(args.trace);
    const std::vector<trace::FrameTrace> frames = reader.read_all();
    const arch::SystemResult result =
        arch::simulate_system(platform, frames, reader.meta(), args.trace);
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / fmt::format("edx-check-{}.db", ::getpid());
    std::filesystem::remove(scratch);
    try {
      const results::RunRows rows = arch::result_rows(result);
      arch::write_results(scratch, rows);
      for (const reports::ComparedBaseline& b : baselines) {
        const arch::Platform other = arch::Platform::load(common::find_resource(b.config).string());
        if (other.name == platform.name) continue;  // this run is that baseline's
        arch::write_results(scratch, arch::result_rows(arch::simulate_system(
                                         other, frames, reader.meta(), args.trace)));
      }
      const reports::ResultsData data = reports::read_results(scratch);
      const reports::RunData* r = data.find(rows.run.run_id);
      if (r == nullptr)
        throw std::logic_error("edx check: the simulated run is not in its database");
      metrics = reports::run_metrics(*r);
      reports::add_baseline_metrics(metrics, data, *r, baselines);
      run_id = r->run_id;
    } catch (...) {
      std::filesystem::remove(scratch);
      throw;
    }
    std::filesystem::remove(scratch);
    metrics["frontend"] = result.frontend.to_json();
  }
  if (!args.characterization.empty()) {
    const std::string text = read_input_file(args.characterization, "characterization file");
    nlohmann::json study;
    try {
      study = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
      throw std::runtime_error(
          fmt::format("{}: expected JSON (edx characterize's "
                      "characterization.json)",
                      args.characterization));
    }
    metrics["characterization"] = reports::characterization_metrics(study, args.characterization);
  }
  const reports::CheckResult check = reports::check_targets(targets, metrics, run_id);
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
  results->excludes(config)->excludes(trace);
  config->needs(trace);
  trace->needs(config);
  cmd->add_option("--run", args->run_id, "Run of the results database (default: its only run)")
      ->needs(results);
  cmd->add_option("--targets", args->targets,
                  "Targets file (default: reports/paper_targets.yaml of edx's data folder, see "
                  "edx --version)");
  cmd->add_option("--characterization", args->characterization,
                  "characterization.json of edx characterize: adds its targets (the paper's "
                  "Sec. III orderings and frame rates); without it they are listed as not run");
  cmd->add_flag("--json", args->json, "Print the table as JSON");
  cmd->callback([args] {
    if (args->results.empty() && args->config.empty()) {
      throw CLI::ValidationError("--results", "give --results or --config and --trace");
    }
    run(*args);
  });
}

}  // namespace edx::cli
