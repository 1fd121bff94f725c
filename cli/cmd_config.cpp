// `edx config`: the reference of every platform key (--reference, docs/CONFIG.md), or a
// platform file resolved (extends merged, defaults filled, checked) as JSON. Logic: arch/system.
#include <fmt/core.h>

#include <memory>
#include <string>

#include "arch/platform/platform.hpp"
#include "cli/commands.hpp"

namespace edx::cli {
namespace {

struct ConfigArguments {
  std::string file;
  bool reference = false;
};

void run(const ConfigArguments& args) {
  if (args.reference == !args.file.empty()) {
    throw CLI::ValidationError("config", "give a platform file or --reference (one of the two)");
  }
  if (args.reference) {
    fmt::print("{}", arch::config_reference_markdown());
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
                "Print the reference of every key as Markdown (docs/CONFIG.md is this output)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
