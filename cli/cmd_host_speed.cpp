// `edx host-speed`: runs the machine-speed reference suite on this machine and prints its times,
// the figures a platform's `host:` states for its CPU (docs/MODEL.md, "Host CPU"). Logic:
// workloads/modes/host_speed_meter.
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "workloads/frontend/trace_meta.hpp"
#include "workloads/modes/host_speed_meter.hpp"

namespace edx::cli {
namespace {

struct HostSpeedArguments {
  int samples = 15;
  bool json = false;
};

void run(const HostSpeedArguments& args) {
  modes::HostSpeedMeterOptions options;
  options.initial_samples = args.samples;
  options.final_samples = 0;
  modes::HostSpeedMeter meter(options);
  meter.start();
  const trace::HostSpeed speed = meter.result();
  const std::string cpu = frontend::cpu_model();
  if (args.json) {
    fmt::print("{}\n",
               nlohmann::json{{"host_cpu", cpu},
                              {"host_speed", nlohmann::json::parse(trace::to_meta_value(speed))}}
                   .dump(2));
    return;
  }
  fmt::print(
      "reference suite v{} on {} ({} samples, median thread CPU time)\n"
      "frontend part  {:.3f} ms\nbackend part   {:.3f} ms\n"
      "as a platform's host:\n  suite: {}\n  frontend_suite_ms: {:.4g}\n  backend_suite_ms: "
      "{:.4g}\n",
      speed.suite, cpu, speed.samples, speed.frontend_ms, speed.backend_ms, speed.suite,
      speed.frontend_ms, speed.backend_ms);
}

}  // namespace

void add_host_speed_command(CLI::App& app) {
  auto args = std::make_shared<HostSpeedArguments>();
  CLI::App* cmd = app.add_subcommand(
      "host-speed",
      "Time the machine-speed reference suite on this machine: the host: suite times of a "
      "platform whose CPU this is (docs/MODEL.md, Host CPU)");
  cmd->add_option("--samples", args->samples, "Passes of each part (the median is reported)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--json", args->json, "Print the result as JSON (only JSON on stdout)");
  cmd->callback([args] { run(*args); });
}

}  // namespace edx::cli
