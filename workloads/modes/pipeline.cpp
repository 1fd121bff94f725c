#include "workloads/modes/pipeline.hpp"

#include <cstdlib>
#include <utility>

#include "workloads/frontend/task_timer.hpp"
#include "workloads/trace/host_clock.hpp"

namespace edx::modes {

namespace {
/// A frame "has GPS" when a fix lies within this time of it.
constexpr std::int64_t kGpsWindowNs = 1'000'000'000;
}  // namespace

trace::PoseArray to_pose_array(const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.rotation());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  const Eigen::Vector3d t = pose.translation();
  return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()};
}

bool gps_near(const std::vector<datasets::GpsFix>& gps, std::int64_t t_ns) {
  const auto it =
      std::lower_bound(gps.begin(), gps.end(), t_ns - kGpsWindowNs,
                       [](const datasets::GpsFix& fix, std::int64_t t) { return fix.t_ns < t; });
  return it != gps.end() && std::llabs(it->t_ns - t_ns) <= kGpsWindowNs;
}

eval::StampedPose stamped(std::int64_t t_ns, std::int64_t index, const Eigen::Isometry3d& pose) {
  eval::StampedPose p;
  p.time_s = static_cast<double>(t_ns) * 1e-9;
  p.frame_index = index;
  p.pose = eval::Pose(pose.matrix());
  return p;
}

std::optional<Eigen::Isometry3d> ground_truth_at(const datasets::Dataset& dataset,
                                                 std::int64_t t_ns) {
  const auto truth =
      datasets::interpolate_ground_truth(dataset.ground_truth(), t_ns, kMaxGroundTruthGapNs);
  if (!truth) return std::nullopt;
  return truth->T_world_body;
}

std::pair<backend::BackendOutput, std::int64_t> run_backend_timed(
    backend::Backend& backend, const backend::BackendInput& input) {
  const frontend::TracingThreads single_threaded(false);
  const std::int64_t start_ns = trace::thread_cpu_ns();
  backend::BackendOutput output = backend.process(input);
  return {std::move(output), trace::thread_cpu_ns() - start_ns};
}

backend::BackendOutput run_backend_on_frame(backend::Backend& backend,
                                            const datasets::Dataset& dataset,
                                            const datasets::StereoFrame& images,
                                            const frontend::FrontendFrame& frontend,
                                            std::int64_t previous_t_ns, trace::FrameRecord& frame) {
  backend::BackendInput input;
  input.t_ns = images.t_ns;
  input.frontend = &frontend;
  input.left_image = &images.left;
  input.imu = between(dataset.imu(), previous_t_ns, images.t_ns);
  input.gps = between(dataset.gps(), previous_t_ns, images.t_ns);
  auto [output, backend_ns] = run_backend_timed(backend, input);
  frame.backend_host_ns = backend_ns;
  frame.backend_status = output.status;
  return std::move(output);
}

void add_kernel_times(KernelSeries& series, std::size_t frame,
                      const std::vector<trace::KernelRecord>& kernels) {
  for (auto& [name, values] : series) values.push_back(0.0);
  for (const trace::KernelRecord& kernel : kernels) {
    std::vector<double>& values = series[kernel.kernel];
    values.resize(frame + 1, 0.0);
    values.back() += static_cast<double>(kernel.host_ns) * 1e-6;
  }
}

}  // namespace edx::modes
