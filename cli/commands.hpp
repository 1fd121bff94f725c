#pragma once
// Subcommands of the `edx` command. Each adds itself to the app; its callback runs the library
// call and throws CLI::RuntimeError(code) to exit with a non-zero status.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "arch/sweep/workload.hpp"

namespace edx::cli {

/// `edx eval`: trajectory error (ATE, RPE, KITTI segment errors) of an estimate file.
void add_eval_command(CLI::App& app);
/// `edx gen`: renders a synthetic dataset of one of the four scenarios in the EuRoC layout.
void add_gen_command(CLI::App& app);
/// `edx trace`: runs the pipeline over a dataset and writes a trace database.
void add_trace_command(CLI::App& app);
/// `edx simulate`: a trace through a platform model.
void add_simulate_command(CLI::App& app);
/// `edx vocab`: bag-of-words vocabulary training.
void add_vocab_command(CLI::App& app);
/// `edx sweep`: a design-space sweep into a results database (docs/SWEEPS.md).
void add_sweep_command(CLI::App& app);
/// `edx export`: a results-database table or a sweep's points as CSV.
void add_export_command(CLI::App& app);
/// `edx report`: HTML report with gnuplot plots of a results database.
void add_report_command(CLI::App& app);
/// Checks shared by every subcommand's options of one kind (issue 21): a path option
/// (--out, --db, --trace, --config, ...) must not be empty, a --seed must not be negative (a
/// uint64 would take -1 as 2^64-1). Call after adding the subcommands.
void check_common_options(CLI::App& app);
/// How a sweep's workload points are traced: as `edx trace --mix` would
/// (workloads/modes/sweep_workload.hpp).
arch::WorkloadTracer mix_tracer();

/// `--workload FILE --seeds LIST --trace-store DIR` of `edx simulate` and `edx check`: the
/// workload of the file traced once per seed (arch/sweep/workload.hpp trace_seeds).
struct SeedOptions {
  std::string workload, seeds, store;
  bool given() const { return !workload.empty(); }
  /// Each seed's trace, traced into the store when missing, `threads` seeds at once.
  std::vector<arch::SeedTrace> traces(int threads) const;
  /// The workload file's parameters (without seed) and their group (arch::seed_group).
  nlohmann::json workload_json() const;
  std::string group() const;
};
/// Adds the three options (each needing the others; --workload excludes `trace`).
void add_seed_options(CLI::App& cmd, SeedOptions& seeds, CLI::Option* trace);

/// A `-j,--jobs` value: itself when given (> 0), else the machine's cores (at least 1).
int jobs_or_cores(int jobs);

/// Accepts a WxH resolution option (datasets::parse_resolution's rules and message).
CLI::Validator resolution_validator();
/// Accepts a finite number > 0 (positive) or >= 0; refuses with "expected a number > 0, got
/// '0'" (CLI11's own CLI::PositiveNumber prints its bound, the largest double, in 309 digits).
CLI::Validator positive_number();
CLI::Validator non_negative_number();
/// `edx host-speed`: the machine-speed reference suite's times on this machine.
void add_host_speed_command(CLI::App& app);
void add_host_costs_command(CLI::App& app);
/// `edx config`: the reference of every platform key, or a platform file resolved.
void add_config_command(CLI::App& app);
/// `edx check`: a run against the paper's Edx-Car figures (reports/paper_targets.yaml).
void add_check_command(CLI::App& app);
/// `edx explain`: a run's critical-path attribution (reports/explain.hpp).
void add_explain_command(CLI::App& app);
/// `edx characterize`: the paper's algorithm characterization (each backend on each scenario).
void add_characterize_command(CLI::App& app);

}  // namespace edx::cli
