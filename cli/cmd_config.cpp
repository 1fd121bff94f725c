// `edx config`: the reference of every platform key and of the other input files' keys
// (--reference, docs/CONFIG.md), or a platform file resolved (extends merged, defaults filled,
// checked) as JSON. Logic: arch/platform, and each input file's reader.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "arch/host/host_costs.hpp"
#include "arch/platform/platform.hpp"
#include "arch/sweep/sweep.hpp"
#include "cli/commands.hpp"
#include "reports/characterization.hpp"
#include "reports/paper_check.hpp"
#include "workloads/modes/sweep_workload.hpp"

namespace edx::cli {
namespace {

/// The keys of the other input files, each read from its field lists as a platform is: sweep
/// specs (and their workload), the paper targets, the host cost table. The end of docs/CONFIG.md.
std::string input_files_reference() {
  std::vector<ReferenceRow> rows = arch::sweep_spec_reference();
  const auto add = [&rows](std::vector<ReferenceRow> more) {
    rows.insert(rows.end(), more.begin(), more.end());
  };
  add(reference_rows("workload", modes::SweepWorkload::fields(), {},
                     "Sweep spec: `workload:` (and the `workload.<key>` parameters)"));
  add(reports::paper_targets_reference());
  add(reports::paper_characterization_reference());
  add(arch::HostCostModel::reference());
  return "\n# Other input files\n\n"
         "Sweep specs (docs/SWEEPS.md), the paper targets (docs/REPORTS.md) and the host cost "
         "table (docs/MODEL.md, \"Host CPU\") are read the same way: each map's keys from a field "
         "list, unknown keys refused, every error one line naming the file, line and key. The "
         "lists of a spec (`parameters`, `objectives`) and the rules between keys are described "
         "with each file.\n" +
         render_reference(rows);
}

struct ConfigArguments {
  std::string file;
  bool reference = false;
};

void run(const ConfigArguments& args) {
  if (args.reference == !args.file.empty()) {
    throw CLI::ValidationError("config", "give a platform file or --reference (one of the two)");
  }
  if (args.reference) {
    fmt::print("{}{}", arch::config_reference_markdown(), input_files_reference());
  } else {
    fmt::print("{}\n", arch::Platform::load(args.file).to_json().dump(2));
  }
}

}  // namespace

void add_config_command(CLI::App& app) {
  auto args = std::make_shared<ConfigArguments>();
  CLI::App* cmd = app.add_subcommand(
      "config",
      "Print every platform key with its unit, default and range (--reference), or a platform "
      "file resolved as JSON");
  cmd->add_option("file", args->file, "Platform description (YAML) to resolve and check");
  cmd->add_flag("--reference", args->reference,
                "Print the reference of every key (platforms, then sweep specs, paper targets and "
                "the host cost table) as Markdown (docs/CONFIG.md is this output)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
