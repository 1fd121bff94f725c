// `edx host-costs`: the op-count host model's cost table (docs/MODEL.md, "Host CPU").
//   fit:   least squares of traces' measured CPU times (over their local suite times) on their
//          work; writes the table (configs/host/host_costs.yaml is the bundled one);
//   check: per kind, a trace's measured against modeled time and R² under a table.
// Logic: arch/host/host_costs.
#include <fmt/core.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "arch/host/host_costs.hpp"
#include "arch/host/throughput.hpp"
#include "cli/commands.hpp"
#include "common/atomic_file.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::cli {
namespace {

struct HostCostsArguments {
  std::vector<std::string> traces;
  std::string out;
  std::string costs;
  std::string provenance;
  std::vector<std::string> only;  ///< re-fit these kinds of `base`, keep the others
  std::string base;
  bool json = false;
};

struct LoadedTrace {
  std::string name;
  std::vector<trace::FrameTrace> frames;
  trace::TraceMeta meta;
};

std::vector<LoadedTrace> load(const std::vector<std::string>& paths) {
  std::vector<LoadedTrace> traces;
  for (const std::string& path : paths) {
    const trace::TraceReader reader(path);
    traces.push_back({path, reader.read_all(), reader.meta()});
  }
  return traces;
}

void fit(const HostCostsArguments& args) {
  // Refused before any work: the table would overwrite its own input.
  for (const std::string& trace : args.traces) {
    std::error_code ec;
    if (std::filesystem::equivalent(trace, args.out, ec)) {
      throw std::runtime_error(fmt::format(
          "{}: --out is a --trace of this fit; writing the table would overwrite its input "
          "(give another --out)",
          args.out));
    }
  }
  const std::vector<LoadedTrace> traces = load(args.traces);
  std::vector<arch::CostFitInput> inputs;
  std::string sources;
  for (const LoadedTrace& t : traces) {
    inputs.push_back({t.name, &t.frames, &t.meta});
    const auto revision = t.meta.find("source_revision");
    const auto cpu = t.meta.find("host_cpu");
    sources += fmt::format("{}{} ({} frames, {}, {})", sources.empty() ? "" : "; ",
                           std::filesystem::path(t.name).filename().string(), t.frames.size(),
                           revision == t.meta.end() ? "?" : revision->second,
                           cpu == t.meta.end() ? "?" : cpu->second);
  }
  const std::string provenance = args.provenance.empty()
                                     ? "fitted by edx host-costs fit on " + sources
                                     : args.provenance + "; fitted on " + sources;
  arch::HostCostModel model = arch::fit_host_costs(inputs, provenance);
  if (!args.only.empty()) {
    const arch::HostCostModel base =
        args.base.empty() ? arch::HostCostModel::bundled() : arch::HostCostModel::load(args.base);
    try {
      model = arch::replace_kinds(base, model, args.only);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("--only: {}", e.what()));
    }
  }
  common::write_file_atomically(
      args.out,
      "# The op-count host model's costs (docs/MODEL.md, \"Host CPU\"): ns per unit of work on a\n"
      "# host whose reference-suite part takes 1 ms. Written by edx host-costs fit; do not "
      "edit.\n" +
          model.to_yaml());
  for (const std::string& warning : arch::fit_warnings(model)) {
    fmt::print(stderr, "edx: warning: {}: {}\n", args.out, warning);
  }
  fmt::print("host costs  {} (suite v{}, {} kinds)\n", args.out, model.suite,
             model.frontend.size() + model.backend.size());
  for (const auto* table : {&model.frontend, &model.backend}) {
    for (const auto& [kind, cost] : *table) {
      fmt::print("  {:<24} {:>6} rows  R² {:>6.3f}  share {:>5.1f} %\n", kind, cost.samples,
                 cost.r2, 100 * cost.measured_share);
    }
  }
}

void check(const HostCostsArguments& args) {
  const arch::HostCostModel model =
      args.costs.empty() ? arch::HostCostModel::bundled() : arch::HostCostModel::load(args.costs);
  nlohmann::json out = nlohmann::json::array();
  for (const LoadedTrace& t : load(args.traces)) {
    out.push_back({{"trace", t.name},
                   {"kinds", arch::compare_host_costs(model, {t.name, &t.frames, &t.meta})}});
  }
  if (args.json) {
    fmt::print("{}\n", out.dump(2));
    return;
  }
  for (const nlohmann::json& t : out) {
    fmt::print("{}\n  {:<24} {:>6} {:>12} {:>12} {:>8} {:>7}\n", t["trace"].get<std::string>(),
               "kind", "rows", "measured", "modeled", "ratio", "R²");
    for (const nlohmann::json& k : t["kinds"]) {
      const double measured = k["measured_ns_per_suite_ms"], modeled = k["modeled_ns_per_suite_ms"];
      fmt::print("  {:<24} {:>6} {:>12.4g} {:>12.4g} {:>8.3f} {:>7.3f}\n",
                 k["kind"].get<std::string>(), k["rows"].get<std::size_t>(), measured, modeled,
                 measured > 0 ? modeled / measured : 0.0, k["r2"].get<double>());
    }
  }
}

}  // namespace

void add_host_costs_command(CLI::App& app) {
  auto args = std::make_shared<HostCostsArguments>();
  CLI::App* cmd = app.add_subcommand(
      "host-costs",
      "The op-count host model's cost table: fit it on traces, or check a trace against it "
      "(docs/MODEL.md, Host CPU)");
  cmd->require_subcommand(1);
  CLI::App* fit_cmd =
      cmd->add_subcommand("fit", "Fit the costs on traces' measured CPU times and write the table");
  fit_cmd->add_option("--trace", args->traces, "Trace(s) to fit on (edx trace)")
      ->required()
      ->check(CLI::ExistingFile);
  fit_cmd->add_option("--out", args->out, "Cost table to write (YAML)")->required();
  fit_cmd->add_option("--provenance", args->provenance,
                      "What the traces are (machine, load, date), kept in the table");
  CLI::Option* only =
      fit_cmd
          ->add_option("--only", args->only,
                       "Re-fit only these kinds (e.g. normal_equations), keeping the others' costs "
                       "from --base")
          ->delimiter(',');
  fit_cmd
      ->add_option("--base", args->base,
                   "The table whose other kinds are kept with --only (default: the bundled "
                   "configs/host/host_costs.yaml)")
      ->check(CLI::ExistingFile)
      ->needs(only);
  fit_cmd->callback([args] { fit(*args); });
  CLI::App* check_cmd =
      cmd->add_subcommand("check", "Per kind, a trace's measured against modeled host time and R²");
  check_cmd->add_option("--trace", args->traces, "Trace(s) to check")
      ->required()
      ->check(CLI::ExistingFile);
  check_cmd->add_option("--costs", args->costs, "Cost table (default: the bundled one)")
      ->check(CLI::ExistingFile);
  check_cmd->add_flag("--json", args->json, "Print JSON only");
  check_cmd->callback([args] { check(*args); });
  cmd->add_subcommand("bounds",
                      "Each kind's throughput bound, which carries its time across processors "
                      "(docs/MODEL.md, Processors from their datasheets)")
      ->callback([] { fmt::print("{}", arch::bounds_markdown()); });
}

}  // namespace edx::cli
