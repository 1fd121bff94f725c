// `edx export results.db --table T --out F.csv` (or --sweep NAME): a results-database table or
// a sweep's points as CSV (docs/SWEEPS.md); `edx export --reference`: every results table and
// column as Markdown (docs/RESULTS.md). Logic: arch/sweep/sweep, arch/results/schema.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "arch/results/schema.hpp"
#include "arch/sweep/sweep.hpp"
#include "cli/commands.hpp"

namespace edx::cli {
namespace {

struct ExportArguments {
  std::string db;
  std::string table;
  std::string sweep;
  std::string out;
  bool reference = false;
};

}  // namespace

void add_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArguments>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write a results-database table or a sweep's points as CSV, or the tables' reference");
  cmd->add_option("db", args->db, "Results database (SQLite)");
  auto* table = cmd->add_option("--table", args->table, "Table to export (e.g. runs, latency)");
  auto* sweep = cmd->add_option("--sweep", args->sweep,
                                "A sweep's points: parameters, metrics, feasible, pareto");
  table->excludes(sweep);
  cmd->add_option("--out", args->out, "CSV file to write");
  cmd->add_flag("--reference", args->reference,
                "Print every results table and column as Markdown (docs/RESULTS.md is this "
                "output)");
  cmd->callback([args] {
    if (args->reference) {
      if (!args->db.empty() || !args->table.empty() || !args->sweep.empty() || !args->out.empty()) {
        throw CLI::ValidationError("--reference", "takes no database, table, sweep or output");
      }
      fmt::print("{}", results::results_reference_markdown());
      return;
    }
    if (args->db.empty()) throw CLI::ValidationError("db", "a results database is required");
    if (args->out.empty()) throw CLI::ValidationError("--out", "a CSV file is required");
    if (args->table.empty() && args->sweep.empty()) {
      throw CLI::ValidationError("--table or --sweep", "one of them is required");
    }
    const std::size_t rows = arch::export_csv(args->db, args->table, args->sweep, args->out);
    fmt::print("exported   {} rows to {}\n", rows, args->out);
  });
}

}  // namespace edx::cli
