// `edx explain RESULTS [--run ID] [--frame N] [--json]`: the critical-path attribution of a run
// (docs/MODEL.md, "Critical-path attribution"): each cause's mean per mode and variant, the
// bottleneck, one frame's causes. Logic: reports/explain.
#include <fmt/core.h>

#include <memory>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "reports/explain.hpp"
#include "reports/results_reader.hpp"

namespace edx::cli {
namespace {

struct ExplainArguments {
  std::string results;
  std::string run_id;
  std::optional<std::int64_t> frame;
  bool json = false;
};

}  // namespace

void add_explain_command(CLI::App& app) {
  auto args = std::make_shared<ExplainArguments>();
  CLI::App* cmd = app.add_subcommand(
      "explain", "Why a run's frames took what they took: each frame's latency split into causes");
  cmd->add_option("results", args->results, "Results database written by edx simulate --out")
      ->required();
  cmd->add_option("--run", args->run_id, "Run of the results database (default: its only run)");
  cmd->add_option("--frame", args->frame, "Also this frame's causes (its trace frame id)");
  cmd->add_flag("--json", args->json, "Print the attribution as JSON");
  cmd->callback([args] {
    const reports::ResultsData data = reports::read_results(args->results);
    const nlohmann::json explained = reports::explain_run(data, {args->run_id, args->frame});
    fmt::print("{}", args->json ? explained.dump(2) + "\n" : reports::format_explain(explained));
  });
}

}  // namespace edx::cli
