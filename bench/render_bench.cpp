// `edx-bench render`: render speed of the synthetic world (workloads/datasets/synthetic), the
// warehouse and the street, at the requested resolution.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json.hpp>

#include "bench/benches.hpp"
#include "workloads/datasets/synthetic/benchmark.hpp"

namespace edx::bench {

void add_render_bench(CLI::App& app) {
  struct Args {
    std::string resolution = "752x480";
    int frames = 60;
    int threads = 2;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "render", "synthetic-world render speed (stereo frames/s, sensor model included)");
  sub->add_option("--resolution", args->resolution, "WxH")->capture_default_str();
  sub->add_option("--frames", args->frames, "stereo frames timed per world")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  sub->add_option("--threads", args->threads, "render threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  sub->add_flag("--json", args->json, "print only a JSON object");
  sub->callback([args] {
    nlohmann::json out = nlohmann::json::array();
    if (!args->json) {
      fmt::print("{:<10} {:>10} {:>8} {:>14} {:>10} {:>12}\n", "world", "resolution", "threads",
                 "stereo fps", "images/s", "ms/stereo");
    }
    for (const bool outdoor : {false, true}) {
      synthetic::RenderBenchmarkOptions options;
      options.outdoor = outdoor;
      options.resolution = synthetic::parse_resolution(args->resolution);
      options.frames = args->frames;
      options.threads = args->threads;
      const synthetic::RenderBenchmarkResult r = synthetic::benchmark_render(options);
      out.push_back({{"world", r.world},
                     {"width", r.width},
                     {"height", r.height},
                     {"threads", r.threads},
                     {"frames", r.frames},
                     {"stereo_frames_per_s", r.stereo_frames_per_s},
                     {"images_per_s", r.images_per_s},
                     {"ms_per_stereo_frame", r.ms_per_stereo_frame},
                     {"rays_per_s", r.rays_per_s}});
      if (!args->json) {
        fmt::print("{:<10} {:>10} {:>8} {:>14.1f} {:>10.1f} {:>12.2f}\n", r.world,
                   fmt::format("{}x{}", r.width, r.height), r.threads, r.stereo_frames_per_s,
                   r.images_per_s, r.ms_per_stereo_frame);
      }
    }
    if (args->json) fmt::print("{}\n", out.dump(2));
  });
}

}  // namespace edx::bench
