#pragma once
// Frontend throughput on this host (`./edx bench frontend`, wired by the bench tool): frames per
// second of StereoFrontend::process at given resolutions, on frames of a real or synthetic
// dataset preloaded into memory (image reading and rectification are not timed).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "workloads/datasets/dataset.hpp"
#include "workloads/frontend/frontend_options.hpp"
#include "workloads/frontend/sample_stats.hpp"

namespace edx::frontend {

struct FrontendBenchmarkOptions {
  std::filesystem::path dataset_path;
  datasets::DatasetFormat format = datasets::DatasetFormat::kEuroc;
  std::string kitti_sequence;  ///< when dataset_path is the KITTI root
  /// Frames are resized to each of these (DatasetOptions::resize) and run separately.
  std::vector<cv::Size> resolutions{{752, 480}, {1280, 720}};
  std::size_t frames = 60;  ///< first N frames of the dataset (fewer if it has fewer)
  std::size_t warmup = 5;   ///< leading frames processed but left out of the figures
  FrontendOptions frontend = [] {
    FrontendOptions o;
    o.count_lk_iterations = false;  // measurement replay, not frontend work
    return o;
  }();
};

struct FrontendBenchmarkResult {
  std::string dataset;  ///< Dataset::name()
  cv::Size resolution;
  std::size_t frames = 0;  ///< timed frames
  double fps = 0;          ///< timed frames / their summed process() wall time
  SampleStats frame_ms;    ///< process() wall time per frame (steady clock)
  /// Timed frames / their summed CPU time of the work (FrontendFrame::host_ns, all threads):
  /// the frame rate on one core.
  double cpu_fps = 0;
  SampleStats frame_cpu_ms;  ///< FrontendFrame::host_ns per frame
  /// Timed frames / their summed FrontendFrame::span_ns: the frame rate on cv::getNumThreads()
  /// cores no other process competes for (a shared machine's wall clock shows less).
  double span_fps = 0;
  std::vector<TaskTimeSummary> tasks;
  double left_keypoints = 0, stereo_matches = 0, tracked = 0;  ///< means per timed frame
};

/// Progress: resolution index, frames done, frames total of that resolution.
using BenchmarkProgress = std::function<void(std::size_t, std::size_t, std::size_t)>;

/// Runs the benchmark; throws std::runtime_error on bad options or dataset errors.
std::vector<FrontendBenchmarkResult> run_frontend_benchmark(const FrontendBenchmarkOptions& options,
                                                            const BenchmarkProgress& progress = {});

nlohmann::json to_json(const std::vector<FrontendBenchmarkResult>& results);
std::string format_benchmark(const std::vector<FrontendBenchmarkResult>& results);

}  // namespace edx::frontend
