// `edx-bench sweep`: design points per second of a sweep (arch/system run_sweep: thread pool,
// shared frontend studies, one SQLite transaction per point) on a trace stretched to N frames
// (2000 by default, as the `system` bench), against issue 44's goal of >= 100 points/s on 2 cores
// (issue 18's was 50; 20 before the whole-system DES).
// Each repeat writes a fresh results database in a temporary directory (no resume).
#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <ctime>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/sweep/sweep.hpp"
#include "bench/benches.hpp"
#include "bench/stretch.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::bench {

void add_sweep_bench(CLI::App& app) {
  struct Args {
    std::string trace;
    std::string spec = std::string(EDX_SOURCE_DIR) + "/sweeps/gemm_block.yaml";
    std::size_t frames = 2000;
    int jobs = 2;
    int repeats = 3;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "sweep", "edx sweep design points per second on a trace stretched to N frames");
  sub->add_option("--trace", args->trace, "trace database (edx trace --backend vio|slam)")
      ->required();
  sub->add_option("--spec", args->spec, "sweep specification")->capture_default_str();
  sub->add_option("--frames", args->frames, "frames: the trace's frames repeated in order")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  sub->add_option("-j,--jobs", args->jobs, "worker threads")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  sub->add_option("--repeats", args->repeats, "timed sweeps (the median is reported)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  sub->add_flag("--json", args->json, "print only a JSON object");
  sub->callback([args] {
    const arch::SweepSpec spec = arch::SweepSpec::load(args->spec);
    const trace::TraceReader reader(args->trace);
    const std::vector<trace::FrameTrace> frames = stretch_trace(reader.read_all(), args->frames);
    if (frames.empty()) throw std::runtime_error(args->trace + ": no frames");
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / fmt::format("edx-bench-sweep-{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::vector<double> rates, cpu_rates;  // points per wall second, per CPU second
    arch::SweepOutcome outcome;
    for (int r = 0; r < args->repeats; ++r) {
      arch::SweepOptions options;
      options.db = dir / fmt::format("r{}.db", r);
      options.jobs = args->jobs;
      const std::clock_t cpu0 = std::clock();
      outcome = arch::run_sweep(spec, options, frames, reader.meta(), args->trace);
      cpu_rates.push_back(double(outcome.computed) /
                          (double(std::clock() - cpu0) / CLOCKS_PER_SEC));
      rates.push_back(double(outcome.computed) / outcome.seconds);
    }
    std::filesystem::remove_all(dir);
    std::sort(rates.begin(), rates.end());
    std::sort(cpu_rates.begin(), cpu_rates.end());
    const double median = rates[rates.size() / 2];
    const double cpu_median = cpu_rates[cpu_rates.size() / 2];
    const nlohmann::json j = {{"spec", args->spec},
                              {"trace", args->trace},
                              {"frames", args->frames},
                              {"points", outcome.total},
                              {"jobs", args->jobs},
                              {"repeats", args->repeats},
                              {"points_per_s", median},
                              {"min_points_per_s", rates.front()},
                              {"max_points_per_s", rates.back()},
                              {"goal_points_per_s", 100.0},
                              {"points_per_cpu_s", cpu_median}};
    if (args->json) {
      fmt::print("{}\n", j.dump(2));
    } else {
      fmt::print(
          "sweep: {} points of {} on {} frames with {} jobs: {:.1f} points/s median of {} (min "
          "{:.1f}, max {:.1f}; goal >= 100); {:.1f} points per CPU second\n",
          outcome.total, spec.name, args->frames, args->jobs, median, args->repeats, rates.front(),
          rates.back(), cpu_median);
    }
  });
}

}  // namespace edx::bench
