#pragma once
// The trace a pipeline run writes, shared by `edx trace` (trace_runner) and `edx trace --mix`
// (mix_runner): the meta every trace carries (docs/TRACE.md, meta table: the runner's keys plus
// the host and build, the frontend options, the OpenCV version and this machine's speed), the
// machine-speed meter sampling beside the frames (host_speed_meter.hpp), the frames appended,
// and the trace renamed into place at the end (TraceWriter: a failed run leaves nothing).
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "workloads/frontend/frontend_options.hpp"
#include "workloads/modes/host_speed_meter.hpp"
#include "workloads/trace/records.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::modes {

/// What a runner says about its run in the trace's meta.
struct TraceRunMeta {
  std::string dataset, sequence, resolution, camera_model;
  /// The runner's pipeline parameters (backend_mode, ...); the session adds "frontend".
  nlohmann::json pipeline_params = nlohmann::json::object();
  std::size_t frames = 0;
  /// The arithmetic of the offloadable backend kernels (meta precision).
  trace::Precision precision = trace::Precision::kFp64;
};

/// Where the trace goes and how the run samples this machine's speed.
struct TraceSessionOptions {
  std::filesystem::path out;
  bool overwrite = false;
  frontend::FrontendOptions frontend;  ///< the run's (recorded; its threading is the meter's)
  HostSpeedMeterOptions host_speed;
};

/// A trace being written. The constructor samples the machine's speed (HostSpeedMeter::start)
/// and creates the temporary trace; nothing appears at `out` before finish().
class TraceSession {
 public:
  TraceSession(const TraceRunMeta& meta, const TraceSessionOptions& options);
  /// Writes one frame, then lets the meter sample when the frames since its last sample took
  /// long enough (the frame's host CPU time: frontend + backend).
  void append(const trace::FrameTrace& record);
  /// The meter's final samples into the meta, then the trace renamed into place.
  void finish();

 private:
  HostSpeedMeter host_speed_;
  trace::TraceWriter writer_;
};

}  // namespace edx::modes
