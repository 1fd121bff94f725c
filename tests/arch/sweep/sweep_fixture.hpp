#pragma once
// A four-frame hand-built trace for sweep tests (the library's and the command's): 40x25
// images, 3 ms frontend and 10 ms backend host time, one offloadable projection kernel a frame
// of 1000, 1500, 2000, 2500 points (5 ms on the host).
#include <filesystem>
#include <string>
#include <string_view>

#include "tests/arch/system/hand_tasks.hpp"
#include "workloads/trace/records.hpp"
#include "workloads/trace/writer.hpp"

namespace edx::arch {

/// A VIO frame with ten hand-sized task rows and one projection kernel of `points` points.
inline trace::FrameTrace sweep_frame(std::int64_t id, std::int64_t points) {
  trace::FrameTrace f;
  f.frame.frame_id = id;
  f.frame.timestamp_ns = 1000 + id;
  f.frame.sequence = "sweep";
  f.frame.mode = trace::BackendMode::Vio;
  f.frame.frontend_host_ns = 3'000'000;
  f.frame.backend_host_ns = 10'000'000;
  f.frame.backend_status = "no pose: hand-built";
  f.tasks = hand_task_rows();
  trace::KernelRecord k;
  k.kernel = "projection";
  k.accelerable = true;
  k.host_ns = 5'000'000;
  k.m = points;
  k.ops = {trace::OpRecord{trace::Op::Gemm, 3, points, 4, 0, 0}};
  f.kernels = {k};
  return f;
}

/// The meta of the sweep tests' traces: every required key, 40x25 at fp64, a 10 ms / 2 ms host.
inline trace::TraceMeta sweep_trace_meta() {
  trace::TraceMeta meta;
  for (std::string_view key : {"dataset", "sequence", "camera_model", "pipeline_params", "host_cpu",
                               "host_cores", "compiler_flags", "source_revision", "created_utc"}) {
    meta[std::string(key)] = "test";
  }
  meta["resolution"] = "40x25";
  meta["precision"] = "fp64";
  meta["host_speed"] = R"({"suite": 1, "frontend_ms": 10.0, "backend_ms": 2.0, "samples": 1})";
  return meta;
}

inline std::filesystem::path write_sweep_trace(const std::filesystem::path& path) {
  trace::TraceWriter writer(path, sweep_trace_meta());
  for (int i = 0; i < 4; ++i) writer.append(sweep_frame(i, 1000 + 500 * i));
  writer.finish();
  return path;
}

}  // namespace edx::arch
