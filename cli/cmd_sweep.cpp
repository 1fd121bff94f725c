// `edx sweep SPEC.yaml --db results.db`: runs (or resumes) a design-space sweep and prints its
// points and Pareto front (docs/SWEEPS.md); under mpirun, spread over the ranks. Logic:
// arch/sweep (sweep.hpp, distributed.hpp); workload points are traced by workloads/modes.
#include <fmt/core.h>

#include <memory>
#include <optional>
#include <string>

#include "arch/sweep/distributed.hpp"
#include "arch/sweep/sweep.hpp"
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "edx_revision.hpp"
#include "workloads/modes/sweep_workload.hpp"

namespace edx::cli {
namespace {

struct SweepArguments {
  std::string spec;
  std::string db;
  std::string trace;
  std::string trace_store;
  int jobs = 0;
  std::size_t limit = 0;
  bool per_frame = false;
  bool json = false;
};

/// The sweep's outcome; nothing on ranks 1..N-1 of an MPI job (rank 0 reports).
std::optional<arch::SweepOutcome> run_here_or_over_mpi(const arch::SweepSpec& spec,
                                                       arch::SweepOptions options) {
  if (!arch::launched_by_mpi()) return arch::run_sweep(spec, options);
  // Under mpirun: rank 0 runs the sweep, the others serve it; a failure on rank 0 ends the job.
  const arch::MpiSession mpi;
  if (mpi.rank() != 0) {
    arch::serve_sweep(spec, options);
    return std::nullopt;
  }
  options.distributed = true;
  try {
    return arch::run_sweep(spec, options);
  } catch (const std::exception& e) {
    fmt::print(stderr, "edx: error: {}\n", e.what());
    mpi.abort(1);
  }
}

void run(const SweepArguments& args) {
  const arch::SweepSpec spec = arch::SweepSpec::load(args.spec);
  arch::SweepOptions options;
  options.db = args.db;
  options.trace = args.trace;
  options.trace_store = args.trace_store;
  options.jobs = jobs_or_cores(args.jobs);
  options.limit = args.limit;
  options.per_frame = args.per_frame;
  options.tracer = mix_tracer();
  auto bar = std::make_shared<ProgressBar>("sweep");
  options.progress = [bar, &spec](std::size_t done, std::size_t total,
                                  const arch::SweepPointResult&) {
    bar->update(done, total, "points", spec.name);
  };
  options.trace_progress = [bar](std::size_t w, const nlohmann::json& workload,
                                 const std::string* error) {  // after each trace
    bar->note(error->empty()
                  ? fmt::format("workload {} traced: {}", w, workload.dump())
                  : fmt::format("workload {} failed: {}: {}", w, workload.dump(), *error));
  };
  const std::optional<arch::SweepOutcome> ran = run_here_or_over_mpi(spec, options);
  if (!ran) return;
  const arch::SweepOutcome& outcome = *ran;
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
  cmd->add_option("--trace-store", args->trace_store,
                  "Folder of the traces of workload points (default: beside --db, "
                  "results.db -> results.traces)");
  cmd->add_option("-j,--jobs", args->jobs,
                  "Points simulated in parallel (default: all cores; under mpirun each rank runs "
                  "one task at a time: start one rank per core)")
      ->check(CLI::Range(1, 256));
  cmd->add_option("--limit", args->limit,
                  "Stop after simulating this many points, at least 1 (a later run resumes; omit "
                  "it for no limit)")
      ->check(CLI::Validator(
          [](const std::string& value) {
            return value.find_first_not_of('0') == std::string::npos
                       ? std::string(
                             "expected a number of points >= 1 (omit --limit for no "
                             "limit)")
                       : std::string();
          },
          "POINTS >= 1"));
  cmd->add_flag("--per-frame", args->per_frame,
                "Also store every point's frames and offload rows (large)");
  cmd->add_flag("--json", args->json, "Print the points and front as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
