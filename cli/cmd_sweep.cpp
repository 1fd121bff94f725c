// `edx sweep SPEC.yaml --db results.db`: runs (or resumes) a design-space sweep and prints its
// points and Pareto front (docs/SWEEPS.md). Logic: arch/sweep/sweep.
#include <fmt/core.h>

#include <memory>
#include <string>
#include <thread>

#include "arch/sweep/sweep.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"

namespace edx::cli {
namespace {

struct SweepArguments {
  std::string spec;
  std::string db;
  std::string trace;
  int jobs = 0;
  std::size_t limit = 0;
  bool per_frame = false;
  bool json = false;
};

void run(const SweepArguments& args) {
  const arch::SweepSpec spec = arch::SweepSpec::load(args.spec);
  arch::SweepOptions options;
  options.db = args.db;
  options.trace = args.trace;
  options.jobs = args.jobs > 0 ? args.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
  options.limit = args.limit;
  options.per_frame = args.per_frame;
  auto bar = std::make_shared<ProgressBar>("sweep");
  options.progress = [bar, &spec](std::size_t done, std::size_t total,
                                  const arch::SweepPointResult&) {
    bar->update(done, total, "points", spec.name);
  };
  const arch::SweepOutcome outcome = arch::run_sweep(spec, options);
  if (args.json) {
    fmt::print("{}\n", outcome.to_json(spec).dump(2));
  } else {
    fmt::print("{}", arch::format_sweep(spec, outcome));
    fmt::print("results    {} (sweep {})\n", args.db, outcome.sweep_id);
  }
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArguments>();
  CLI::App* cmd = app.add_subcommand(
      "sweep", "Run a design-space sweep (sweeps/*.yaml) into a results database; resumable");
  cmd->add_option("spec", args->spec, "Sweep specification (YAML)")->required();
  cmd->add_option("--db", args->db, "Results database (SQLite); points already in it are skipped")
      ->required();
  cmd->add_option("--trace", args->trace, "Trace database (overrides the spec's trace:)");
  cmd->add_option("-j,--jobs", args->jobs, "Points simulated in parallel (default: all cores)")
      ->check(CLI::Range(1, 256));
  cmd->add_option("--limit", args->limit,
                  "Stop after simulating this many points (a later run resumes)");
  cmd->add_flag("--per-frame", args->per_frame,
                "Also store every point's frames and offload rows (large)");
  cmd->add_flag("--json", args->json, "Print the points and front as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
