// `edx report`: an HTML report (plots by gnuplot, tables of every summary figure) of a results
// database written by `edx simulate --out`. Logic: reports/html_report (docs/REPORTS.md).
#include <fmt/core.h>

#include <string>

#include "cli/commands.hpp"
#include "reports/html_report.hpp"
#include "reports/results_reader.hpp"

namespace edx::cli {
namespace {

struct ReportArguments {
  std::string results;
  std::string out;
  std::string trace;
  std::string characterization;
};

void run(const ReportArguments& args) {
  const reports::ResultsData data = reports::read_results(args.results);
  reports::ReportOptions options;
  options.out_dir = args.out;
  options.trace = args.trace;
  options.characterization = args.characterization;
  const reports::ReportResult result = reports::write_report(data, options);
  if (!result.plotted) fmt::print(stderr, "edx: warning: gnuplot not found, tables only\n");
  fmt::print("report     {} ({} runs, {} plots)\n", result.index.string(), data.runs.size(),
             result.images.size());
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto args = std::make_shared<ReportArguments>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Write an HTML report with plots (gnuplot) of a results database");
  cmd->add_option("results", args->results, "Results database written by edx simulate --out")
      ->required();
  cmd->add_option("--out", args->out, "Directory of the report (DIR/index.html)")->required();
  cmd->add_option("--trace", args->trace, "Trace database whose metadata the report shows");
  cmd->add_option("--characterization", args->characterization,
                  "characterization.json of edx characterize: the paper's Sec. III figure with "
                  "edx's points (docs/CHARACTERIZATION.md)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
