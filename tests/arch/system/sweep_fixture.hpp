#pragma once
// A four-frame hand-built trace for sweep tests (the library's and the command's): 40x25
// images, 3 ms frontend and 10 ms backend host time, one offloadable projection kernel a frame
// of 1000, 1500, 2000, 2500 points (5 ms on the host).
#include <filesystem>
#include <string>
#include <string_view>

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
  using trace::Image;
  using trace::Task;
  const auto task = [](Task t, Image i, std::int64_t pixels, std::int64_t window) {
    trace::TaskRecord r;
    r.task = t;
    r.image = i;
    r.pixels = pixels;
    r.levels = pixels > 0 ? 1 : 0;
    r.window_size = window;
    if (pixels > 0) r.per_level = {trace::LevelWork{0, 40, 25, pixels, 0, 0}};
    return r;
  };
  f.tasks = {task(Task::FD, Image::Left, 1000, 0),  task(Task::IF, Image::Left, 1000, 7),
             task(Task::FD, Image::Right, 1000, 0), task(Task::IF, Image::Right, 1000, 7),
             task(Task::DC, Image::Left, 1000, 3),  task(Task::LSS, Image::Left, 0, 21),
             task(Task::FC, Image::Left, 0, 31),    task(Task::FC, Image::Right, 0, 31),
             task(Task::MO, Image::Stereo, 0, 0),   task(Task::DR, Image::Stereo, 0, 11)};
  f.tasks[0].candidates = f.tasks[2].candidates = 10;
  f.tasks[9].search_range = 11;
  trace::KernelRecord k;
  k.kernel = "projection";
  k.accelerable = true;
  k.host_ns = 5'000'000;
  k.m = points;
  k.ops = {trace::OpRecord{trace::Op::Gemm, 3, points, 4, 0, 0}};
  f.kernels = {k};
  return f;
}

inline std::filesystem::path write_sweep_trace(const std::filesystem::path& path) {
  trace::TraceMeta meta;
  for (std::string_view key : {"dataset", "sequence", "camera_model", "pipeline_params", "host_cpu",
                               "host_cores", "compiler_flags", "source_revision", "created_utc"}) {
    meta[std::string(key)] = "test";
  }
  meta["resolution"] = "40x25";
  trace::TraceWriter writer(path, meta);
  for (int i = 0; i < 4; ++i) writer.append(sweep_frame(i, 1000 + 500 * i));
  writer.finish();
  return path;
}

}  // namespace edx::arch
