// Entry point of `edx-bench` (run as `./edx bench NAME ...`): registers the benchmarks and maps
// failures to exit codes: 0 success, 1 failed benchmark (one-line message), 2 bad command line.
#include <fmt/core.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <string>

#include "bench/benches.hpp"

int main(int argc, char** argv) {
  // Log lines (a dataset's warnings) go to stderr: stdout carries only the results (--json).
  spdlog::set_default_logger(spdlog::stderr_color_mt("edx-bench"));
  CLI::App app{"edx-bench: benchmarks of edx (run as ./edx bench NAME ...)", "edx-bench"};
  app.require_subcommand(1);

  edx::bench::add_des_bench(app);
  edx::bench::add_render_bench(app);
  edx::bench::add_frontend_bench(app);
  edx::bench::add_system_bench(app);
  edx::bench::add_sweep_bench(app);
  edx::bench::add_sweep_mpi_bench(app);
  edx::bench::add_host_load_bench(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (const auto newline = message.find('\n'); newline != std::string::npos) {
      message.resize(newline);
    }
    fmt::print(stderr, "edx-bench: {} (see edx-bench --help)\n", message);
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "edx-bench: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
