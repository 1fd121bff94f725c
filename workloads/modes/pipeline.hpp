#pragma once
// Pieces of the per-frame pipeline shared by the single-dataset runner (trace_runner) and the
// mixed-sequence runner (mix_runner): the backend's run on a frame and its kernels' host times,
// pose conversions, stream slicing, ground truth lookup.
#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "workloads/backend/backend.hpp"
#include "workloads/datasets/dataset.hpp"
#include "workloads/eval/trajectory.hpp"
#include "workloads/frontend/stereo_frontend.hpp"
#include "workloads/trace/records.hpp"

namespace edx::modes {

/// Runs the backend on one frame and returns its output with the CPU time of its work, ns:
/// the calling thread's CPU time, OpenCV single-threaded meanwhile (frontend::TracingThreads),
/// so that neither the pool's idle threads nor their waiting count (docs/TRACE.md, Host times).
std::pair<backend::BackendOutput, std::int64_t> run_backend_timed(
    backend::Backend& backend, const backend::BackendInput& input);

/// Runs `backend` on the frame at images.t_ns with the IMU samples and GPS fixes since
/// previous_t_ns, and records its host time and status in `frame`.
backend::BackendOutput run_backend_on_frame(backend::Backend& backend,
                                            const datasets::Dataset& dataset,
                                            const datasets::StereoFrame& images,
                                            const frontend::FrontendFrame& frontend,
                                            std::int64_t previous_t_ns, trace::FrameRecord& frame);

/// Per-kernel host time series, ms per frame by kernel name (0 on frames where it did not run).
using KernelSeries = std::map<std::string, std::vector<double>>;

/// Adds frame number `frame` (0-based, the frames before it already in `series`): every known
/// kernel's series gets a 0, then each kernel's host time is added to its series (a new kernel's
/// series padded with 0 for the frames before).
void add_kernel_times(KernelSeries& series, std::size_t frame,
                      const std::vector<trace::KernelRecord>& kernels);

/// Ground truth is interpolated between samples at most this far apart.
inline constexpr std::int64_t kMaxGroundTruthGapNs = 250'000'000;

/// tx, ty, tz, qw, qx, qy, qz with qw >= 0 (one sign for one rotation).
trace::PoseArray to_pose_array(const Eigen::Isometry3d& pose);

/// Whether a GPS fix lies within 1 s of t_ns (the trace's `gps_available`).
bool gps_near(const std::vector<datasets::GpsFix>& gps, std::int64_t t_ns);

/// Elements of a time-sorted stream with t_begin < t <= t_end.
template <class Sample>
std::span<const Sample> between(const std::vector<Sample>& samples, std::int64_t t_begin,
                                std::int64_t t_end) {
  const auto after = [](std::int64_t t, const Sample& s) { return t < s.t_ns; };
  const auto first = std::upper_bound(samples.begin(), samples.end(), t_begin, after);
  const auto last = std::upper_bound(first, samples.end(), t_end, after);
  return {first, last};
}

/// A pose stamped with its frame time (s) and index, for eval::evaluate.
eval::StampedPose stamped(std::int64_t t_ns, std::int64_t index, const Eigen::Isometry3d& pose);

/// The dataset's ground-truth body pose at t_ns, when its samples bracket t_ns closely enough.
std::optional<Eigen::Isometry3d> ground_truth_at(const datasets::Dataset& dataset,
                                                 std::int64_t t_ns);

}  // namespace edx::modes
