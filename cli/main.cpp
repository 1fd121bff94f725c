// Entry point of the `edx` command: registers the subcommands and maps failures to exit codes:
// 0 success, 1 bad input or failed work (one-line message), 2 bad command line.
#include <fmt/core.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <system_error>

#include "cli/commands.hpp"
#include "cli/version.hpp"
#include "common/resources.hpp"
#include "edx_revision.hpp"

namespace {

constexpr const char* kDescription =
    "edx: design-space exploration of localization accelerators (after the Eudoxus paper).\n"
    "Benchmarks run through the bootstrap script: ./edx bench des [--json]";

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("edx"));
  spdlog::set_pattern("edx: %^%l%$: %v");

  CLI::App app{kDescription, "edx"};
  // The second line names the folder edx reads its own files from (common/resources.hpp).
  app.set_version_flag("--version", [] {
    const edx::common::DataRoot data = edx::common::data_root();
    return fmt::format("edx {} ({})\ndata: {} ({})", edx::cli::kVersion, edx::kSourceRevision,
                       data.path.empty() ? "-" : data.path.string(), data.how);
  });
  // At most one subcommand; a missing one is reported after parsing so that an unknown word
  // is named as such rather than as a missing subcommand (CLI11 checks requirements first).
  app.require_subcommand(0, 1);
  app.fallthrough(false);

  edx::cli::add_eval_command(app);
  edx::cli::add_gen_command(app);
  edx::cli::add_trace_command(app);
  edx::cli::add_simulate_command(app);
  edx::cli::add_vocab_command(app);
  edx::cli::add_sweep_command(app);
  edx::cli::add_export_command(app);
  edx::cli::add_report_command(app);
  edx::cli::add_check_command(app);
  edx::cli::add_explain_command(app);
  edx::cli::add_characterize_command(app);
  edx::cli::add_config_command(app);
  edx::cli::add_host_speed_command(app);
  edx::cli::add_host_costs_command(app);
  edx::cli::check_common_options(app);

  try {
    app.parse(argc, argv);
    if (app.get_subcommands().empty()) {
      fmt::print(stderr, "edx: a subcommand is required (see edx --help)\n");
      return 2;
    }
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a subcommand already reported its failure
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (const auto newline = message.find('\n'); newline != std::string::npos) {
      message.resize(newline);
    }
    fmt::print(stderr, "edx: {} (see edx --help)\n", message);
    return 2;
  } catch (const std::system_error& e) {
    // fmt::print to a full or closed standard output (commands print their results there).
    if (std::string_view(e.what()).starts_with("cannot write to file")) {
      fmt::print(stderr, "edx: error: standard output: write failed ({})\n", e.code().message());
    } else {
      fmt::print(stderr, "edx: error: {}\n", e.what());
    }
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "edx: error: {}\n", e.what());
    return 1;
  }
  // What the command printed must have reached standard output (a full device, a closed pipe):
  // a result nobody received is a failure, not a success.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    fmt::print(stderr, "edx: error: standard output: write failed ({})\n", std::strerror(errno));
    return 1;
  }
  return 0;
}
