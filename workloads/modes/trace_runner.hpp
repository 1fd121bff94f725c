#pragma once
// The pipeline runner behind `edx trace`: opens a dataset, runs the stereo frontend on every
// frame and, when one is given, a backend on its features with the IMU samples and GPS fixes
// since the previous frame; writes the trace (docs/TRACE.md): one frames row (with the estimated
// pose), ten tasks rows and the backend's kernels and ops per frame; and measures the estimate
// against the ground truth. Without a backend, frames carry backend_mode none and no estimated
// pose. The trace is written to a temporary file and renamed at the end (TraceWriter): a failed
// run leaves nothing.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "workloads/backend/backend.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/eval/evaluate.hpp"
#include "workloads/frontend/frontend_options.hpp"
#include "workloads/frontend/sample_stats.hpp"
#include "workloads/modes/host_speed_meter.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

using frontend::FrontendOptions;
using frontend::SampleStats;
using frontend::TaskTimeSummary;

/// Builds the backend for a dataset (calibration, IMU noise); see make_backend_factory.
using BackendFactory =
    std::function<std::unique_ptr<backend::Backend>(const datasets::Dataset& dataset)>;

struct TraceRunOptions {
  std::filesystem::path dataset_path;
  datasets::DatasetFormat format = datasets::DatasetFormat::kEuroc;
  datasets::DatasetOptions dataset;       ///< resize (--resolution), KITTI sequence
  std::optional<std::size_t> max_frames;  ///< first N frames only (--frames)
  std::filesystem::path out;
  bool overwrite = false;  ///< replace an existing trace (--force)
  /// Scenario written on every frame; default: outdoor_unknown for KITTI and for EuRoC-layout
  /// data with GPS, indoor_unknown otherwise (the *_known variants with the registration
  /// backend, whose frames are also marked map_available).
  std::optional<trace::Scenario> scenario;
  /// Frontend options. Traces run the tasks one after another by default, each on the calling
  /// thread (OpenCV single-threaded while tracing, frontend::TracingThreads), so that each task's
  /// host time (thread CPU time, workloads/trace/host_clock.hpp) is all of its own work.
  FrontendOptions frontend = [] {
    FrontendOptions o;
    o.parallel_images = false;
    return o;
  }();
  /// The backend run on every frame; empty: frontend only.
  BackendFactory make_backend;
  /// The precision make_backend's backend computes its offloadable kernels at (meta precision;
  /// backend_factory takes the same value).
  trace::Precision precision = trace::Precision::kFp64;
  /// Where to save the map the backend built (--save-map); only the SLAM backend builds one.
  std::optional<std::filesystem::path> map_out;
  /// Alignment of the estimate to the ground truth for the accuracy figures; default: position
  /// and yaw when the dataset has an IMU (gravity is observable), SE(3) otherwise.
  std::optional<eval::AlignmentMethod> alignment;
  /// When the machine-speed reference suite samples (meta host_speed).
  HostSpeedMeterOptions host_speed;
};

struct TraceRunSummary {
  std::filesystem::path out;
  std::string dataset;     ///< meta.dataset
  std::string sequence;    ///< meta.sequence
  std::string resolution;  ///< meta.resolution
  std::string scenario;
  std::size_t frames = 0;
  std::size_t ground_truth_frames = 0;  ///< frames with a ground-truth pose
  std::vector<TaskTimeSummary> tasks;   ///< in row order (FD L, IF L, ...)
  SampleStats frontend_ms;              ///< wall time of the whole frontend per frame
  SampleStats left_keypoints, right_keypoints, tracked, new_features, stereo_matches;
  double wall_seconds = 0;  ///< whole run, including reading images and writing
  std::string backend_mode = "none";
  SampleStats backend_ms;            ///< backend wall time per frame (frames it ran on)
  std::size_t estimated_frames = 0;  ///< frames with an estimated pose
  /// Accuracy of the estimate against the ground truth, when both exist for enough frames.
  std::optional<eval::EvalResult> accuracy;
  /// Backend kernel host times per frame (ms), by kernel name, summed over its invocations in
  /// the frame; frames where a kernel did not run count as 0.
  std::vector<std::pair<std::string, SampleStats>> kernel_ms;
  /// The saved map (map_out): its file, keyframes and landmarks.
  std::optional<std::filesystem::path> map_out;
  std::size_t map_keyframes = 0, map_landmarks = 0;
};

/// Progress: frames done, frames total.
using TraceProgress = std::function<void(std::size_t done, std::size_t total)>;

/// Runs the frontend over the dataset and writes the trace. Throws std::runtime_error with a
/// one-line message naming the file, frame or option on bad input (unreadable or missing image,
/// image size changing mid-sequence, existing output without overwrite, no frames).
TraceRunSummary run_trace(const TraceRunOptions& options, const TraceProgress& progress = {});

/// The sequence name a trace records, e.g. "euroc:V1_01_easy" (the folder holding mav0/) or
/// "kitti:01" (the sequence folder or options.kitti_sequence).
std::string sequence_name(const std::filesystem::path& dataset_path, datasets::DatasetFormat format,
                          const datasets::DatasetOptions& options);

/// Machine-readable summary (`edx trace --json`).
nlohmann::json to_json(const TraceRunSummary& summary);
/// Human-readable summary: a few header lines and a table of task times.
std::string format_summary(const TraceRunSummary& summary);

}  // namespace edx::modes
