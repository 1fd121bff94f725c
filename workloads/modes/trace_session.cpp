#include "workloads/modes/trace_session.hpp"

#include <opencv2/core/version.hpp>

#include "workloads/frontend/trace_meta.hpp"

namespace edx::modes {
namespace {

/// The runner's meta plus the host and build keys, pipeline_params with the frontend options,
/// and the OpenCV version.
trace::TraceMeta trace_meta(const TraceRunMeta& run, const frontend::FrontendOptions& frontend) {
  trace::TraceMeta meta = frontend::host_and_build_meta();
  meta["dataset"] = run.dataset;
  meta["sequence"] = run.sequence;
  meta["resolution"] = run.resolution;
  meta["camera_model"] = run.camera_model;
  nlohmann::json params = run.pipeline_params;
  params["frontend"] = frontend::to_json(frontend);
  meta["pipeline_params"] = params.dump();
  meta["frames"] = std::to_string(run.frames);
  meta["precision"] = trace::to_string(run.precision);
  meta["opencv_version"] = CV_VERSION;
  return meta;
}

/// The meter in the frontend's threading (HostSpeedMeterOptions::parallel_images).
HostSpeedMeterOptions meter_options(const TraceSessionOptions& options) {
  HostSpeedMeterOptions meter = options.host_speed;
  meter.parallel_images = options.frontend.parallel_images;
  return meter;
}

/// `meta` with the meter's first samples (taken here) as host_speed.
trace::TraceMeta with_host_speed(trace::TraceMeta meta, HostSpeedMeter& host_speed) {
  host_speed.start();
  meta["host_speed"] = trace::to_meta_value(host_speed.result());
  return meta;
}

trace::TraceWriterOptions writer_options(const TraceSessionOptions& options) {
  trace::TraceWriterOptions writer;
  writer.overwrite = options.overwrite;
  return writer;
}

}  // namespace

TraceSession::TraceSession(const TraceRunMeta& meta, const TraceSessionOptions& options)
    : host_speed_(meter_options(options)),
      writer_(options.out, with_host_speed(trace_meta(meta, options.frontend), host_speed_),
              writer_options(options)) {}

void TraceSession::append(const trace::FrameTrace& record) {
  writer_.append(record);
  host_speed_.after_frame(record.frame.frontend_host_ns + record.frame.backend_host_ns);
}

void TraceSession::finish() {
  host_speed_.finish_into(writer_);
  writer_.finish();
}

}  // namespace edx::modes
