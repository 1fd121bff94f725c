#include "workloads/frontend/benchmark.hpp"

#include <fmt/core.h>

#include <chrono>
#include <stdexcept>

#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {

std::vector<FrontendBenchmarkResult> run_frontend_benchmark(const FrontendBenchmarkOptions& options,
                                                            const BenchmarkProgress& progress) {
  options.frontend.validate();
  if (options.frames <= options.warmup) {
    throw std::runtime_error(fmt::format("benchmark frames = {} (expected more than warmup = {})",
                                         options.frames, options.warmup));
  }
  // Without parallel_images, OpenCV on the calling thread alone (as tracing does).
  const TracingThreads threads(options.frontend.parallel_images);
  std::vector<FrontendBenchmarkResult> results;
  for (std::size_t r = 0; r < options.resolutions.size(); ++r) {
    datasets::DatasetOptions dataset_options;
    dataset_options.resize = options.resolutions[r];
    dataset_options.kitti_sequence = options.kitti_sequence;
    const auto dataset =
        datasets::open_dataset(options.dataset_path, options.format, dataset_options);
    const std::size_t frames = std::min(options.frames, dataset->frame_count());
    if (frames <= options.warmup) {
      throw std::runtime_error(fmt::format("{}: {} frames (the benchmark needs more than {})",
                                           dataset->name(), frames, options.warmup));
    }
    std::vector<datasets::StereoFrame> images;
    for (std::size_t i = 0; i < frames; ++i) images.push_back(dataset->load_frame(i));
    const datasets::StereoCalibration& calibration = dataset->calibration();
    StereoFrontend frontend(options.frontend, {calibration.rectified.fx, calibration.baseline_m});

    FrontendBenchmarkResult result;
    result.dataset = dataset->name();
    result.resolution = options.resolutions[r];
    std::vector<double> frame_ms, frame_cpu_ms;
    std::vector<std::vector<double>> task_ms;
    double total_ms = 0, total_cpu_ms = 0, total_span_ms = 0;
    for (std::size_t i = 0; i < frames; ++i) {
      const auto start = std::chrono::steady_clock::now();
      const FrontendFrame out = frontend.process(images[i].left, images[i].right);
      const std::chrono::duration<double, std::milli> wall =
          std::chrono::steady_clock::now() - start;
      if (progress) progress(r, i + 1, frames);
      if (i < options.warmup) continue;
      frame_ms.push_back(wall.count());
      total_ms += wall.count();
      const double cpu_ms = static_cast<double>(out.host_ns) * 1e-6;
      frame_cpu_ms.push_back(cpu_ms);
      total_cpu_ms += cpu_ms;
      total_span_ms += static_cast<double>(out.span_ns) * 1e-6;
      if (task_ms.empty()) {
        task_ms.resize(out.tasks.size());
        for (const trace::TaskRecord& t : out.tasks) {
          result.tasks.push_back({t.task, t.image, {}});
        }
      }
      for (std::size_t t = 0; t < out.tasks.size() && t < task_ms.size(); ++t) {
        task_ms[t].push_back(static_cast<double>(out.tasks[t].host_ns) * 1e-6);
      }
      result.left_keypoints += out.stats.left_keypoints;
      result.stereo_matches += out.stats.stereo_matches;
      result.tracked += out.stats.tracked;
    }
    result.frames = frame_ms.size();
    const double n = static_cast<double>(result.frames);
    result.fps = total_ms > 0 ? 1000.0 * n / total_ms : 0;
    result.frame_ms = summarize(frame_ms);
    result.cpu_fps = total_cpu_ms > 0 ? 1000.0 * n / total_cpu_ms : 0;
    result.frame_cpu_ms = summarize(frame_cpu_ms);
    result.span_fps = total_span_ms > 0 ? 1000.0 * n / total_span_ms : 0;
    for (std::size_t t = 0; t < task_ms.size(); ++t) result.tasks[t].ms = summarize(task_ms[t]);
    result.left_keypoints /= n;
    result.stereo_matches /= n;
    result.tracked /= n;
    results.push_back(std::move(result));
  }
  return results;
}

nlohmann::json to_json(const std::vector<FrontendBenchmarkResult>& results) {
  nlohmann::json out = nlohmann::json::array();
  for (const FrontendBenchmarkResult& r : results) {
    nlohmann::json tasks = nlohmann::json::object();
    for (const TaskTimeSummary& t : r.tasks) {
      tasks[fmt::format("{}/{}", trace::to_string(t.task), trace::to_string(t.image))] = {
          {"mean_ms", t.ms.mean}, {"p99_ms", t.ms.p99}};
    }
    out.push_back({{"dataset", r.dataset},
                   {"resolution", fmt::format("{}x{}", r.resolution.width, r.resolution.height)},
                   {"frames", r.frames},
                   {"fps", r.fps},
                   {"frame_ms",
                    {{"mean", r.frame_ms.mean},
                     {"sd", r.frame_ms.sd},
                     {"p50", r.frame_ms.p50},
                     {"p99", r.frame_ms.p99},
                     {"max", r.frame_ms.max}}},
                   {"cpu_fps", r.cpu_fps},
                   {"span_fps", r.span_fps},
                   {"frame_cpu_ms", {{"mean", r.frame_cpu_ms.mean}, {"p99", r.frame_cpu_ms.p99}}},
                   {"task_ms", tasks},
                   {"left_keypoints", r.left_keypoints},
                   {"stereo_matches", r.stereo_matches},
                   {"tracked", r.tracked}});
  }
  return out;
}

std::string format_benchmark(const std::vector<FrontendBenchmarkResult>& results) {
  std::string text = fmt::format("{:<11} {:>7} {:>9} {:>9} {:>7} {:>8} {:>9} {:>7} {:>7}  {}\n",
                                 "resolution", "fps", "mean ms", "p99 ms", "cpu fps", "span fps",
                                 "keypts", "stereo", "frames", "dataset");
  for (const FrontendBenchmarkResult& r : results) {
    text += fmt::format(
        "{:<11} {:>7.1f} {:>9.2f} {:>9.2f} {:>7.1f} {:>8.1f} {:>9.0f} {:>7.0f} {:>7}  {}\n",
        fmt::format("{}x{}", r.resolution.width, r.resolution.height), r.fps, r.frame_ms.mean,
        r.frame_ms.p99, r.cpu_fps, r.span_fps, r.left_keypoints, r.stereo_matches, r.frames,
        r.dataset);
  }
  return text;
}

}  // namespace edx::frontend
