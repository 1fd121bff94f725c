// Options and helpers shared by several subcommands (commands.hpp): the common checks of path and
// seed options, the workload tracer of sweeps, the --workload/--seeds/--trace-store options.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <thread>

#include "cli/commands.hpp"
#include "edx_revision.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/modes/sweep_workload.hpp"

namespace edx::cli {

int jobs_or_cores(int jobs) {
  return jobs > 0 ? jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void check_common_options(CLI::App& app) {
  static constexpr std::array<std::string_view, 14> kPathOptions{
      "out",     "db",  "trace", "config", "data", "results",  "timeline",
      "dataset", "map", "vocab", "gt",     "est",  "save-map", "datasets"};
  const CLI::Validator non_empty(
      [](std::string& value) {
        return value.empty() ? std::string("expected a path, got ''") : std::string();
      },
      "PATH");
  const CLI::Validator non_negative(
      [](std::string& value) {
        const bool digits = !value.empty() && value.find_first_not_of("0123456789") == value.npos;
        return digits ? std::string() : "expected a non-negative integer, got '" + value + "'";
      },
      "UINT");
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    for (CLI::Option* option : command->get_options([](CLI::Option*) { return true; })) {
      for (const std::string& name : option->get_lnames()) {
        for (std::string_view path : kPathOptions) {
          if (name == path) option->check(non_empty);
        }
        if (name == "seed") option->check(non_negative);
      }
    }
  }
}

CLI::Validator resolution_validator() {
  return CLI::Validator(
      [](std::string& text) {
        try {
          datasets::parse_resolution(text);
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
        return std::string();
      },
      "WxH");
}

namespace {

/// A finite number whose value `accepts`, else "expected a number <bound>, got '<text>'".
CLI::Validator number_validator(bool (*accepts)(double), const std::string& bound,
                                const std::string& name) {
  return CLI::Validator(
      [accepts, bound](std::string& text) {
        double value = 0;
        const char* end = text.data() + text.size();
        const auto [at, error] = std::from_chars(text.data(), end, value);
        const bool ok = !text.empty() && error == std::errc() && at == end &&
                        std::isfinite(value) && accepts(value);
        return ok ? std::string() : fmt::format("expected a number {}, got '{}'", bound, text);
      },
      name);
}

}  // namespace

CLI::Validator positive_number() {
  return number_validator([](double v) { return v > 0; }, "> 0", "POSITIVE");
}

CLI::Validator non_negative_number() {
  return number_validator([](double v) { return v >= 0; }, ">= 0", "NONNEGATIVE");
}

arch::WorkloadTracer mix_tracer() {
  return {[](const nlohmann::json& workload) {
            return modes::SweepWorkload::from_json(workload).to_json();
          },
          [](const nlohmann::json& resolved, const std::filesystem::path& out,
             const std::filesystem::path& data_dir) {
            modes::trace_sweep_workload(modes::SweepWorkload::from_json(resolved), out, data_dir);
          },
          kSourceRevision};
}

void add_seed_options(CLI::App& cmd, SeedOptions& seeds, CLI::Option* trace) {
  auto* workload = cmd.add_option(
      "--workload", seeds.workload,
      "Instead of --trace: a workload file (YAML map of a sweep's workload parameters: mix, "
      "frames, resolution, ...; docs/SWEEPS.md), traced once per seed into --trace-store");
  auto* list = cmd.add_option("--seeds", seeds.seeds,
                              "With --workload: the seeds, e.g. 1-5 or 1,3,7; every figure as "
                              "its mean and 95 % interval (Student t)");
  auto* store = cmd.add_option("--trace-store", seeds.store,
                               "With --workload: the folder of the seeds' traces (reused)");
  workload->needs(list)->needs(store)->excludes(trace);
  list->needs(workload);
  store->needs(workload);
}

nlohmann::json SeedOptions::workload_json() const { return arch::load_workload_file(workload); }

std::string SeedOptions::group() const { return arch::seed_group(mix_tracer(), workload_json()); }

std::vector<arch::SeedTrace> SeedOptions::traces(int threads) const {
  return arch::trace_seeds(
      mix_tracer(), arch::load_workload_file(workload), arch::parse_seed_list(seeds), store,
      [this](std::uint64_t seed) {
        fmt::print(stderr, "edx: seed {}: tracing {} into {}\n", seed, workload, store);
      },
      threads);
}

}  // namespace edx::cli
