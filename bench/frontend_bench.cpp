// `edx-bench frontend`: frames per second of the stereo frontend (workloads/frontend) on frames
// of a dataset preloaded into memory, at one or more resolutions.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "bench/benches.hpp"
#include "workloads/frontend/benchmark.hpp"

namespace edx::bench {

void add_frontend_bench(CLI::App& app) {
  struct Args {
    std::string dataset = std::string(EDX_SHARED_DATA_DIR) + "/euroc_v101_micro";
    std::string format = "euroc";
    std::vector<std::string> resolutions{"752x480", "1280x720"};
    std::size_t frames = 60;
    bool json = false;
    bool serial = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("frontend", "stereo frontend frames/s per resolution");
  sub->add_option("--dataset", args->dataset, "dataset folder")->capture_default_str();
  sub->add_option("--format", args->format, "euroc|kitti")->capture_default_str();
  sub->add_option("--resolution", args->resolutions, "WxH, repeatable")->capture_default_str();
  sub->add_option("--frames", args->frames, "frames per resolution (5 warm-up frames excluded)")
      ->check(CLI::Range(6, 100000))
      ->capture_default_str();
  sub->add_flag("--json", args->json, "print only a JSON object");
  sub->add_flag("--serial", args->serial,
                "tasks one after another, OpenCV on one thread (as `edx trace` without "
                "--parallel): every instruction on the calling thread, for profiling");
  sub->callback([args] {
    frontend::FrontendBenchmarkOptions options;
    options.dataset_path = args->dataset;
    options.format = datasets::parse_dataset_format(args->format);
    options.resolutions.clear();
    for (const auto& text : args->resolutions) {
      options.resolutions.push_back(datasets::parse_resolution(text));
    }
    options.frames = args->frames;
    options.frontend.parallel_images = !args->serial;
    const auto results = frontend::run_frontend_benchmark(options);
    if (args->json) {
      fmt::print("{}\n", frontend::to_json(results).dump(2));
    } else {
      fmt::print("{}", frontend::format_benchmark(results));
    }
  });
}

}  // namespace edx::bench
