#pragma once
// The ten frontend task rows of a hand-built frame (docs/TRACE.md) shared by the system and sweep
// tests: work only in FD, IF (1000 pixels an image of a 40x25 level, 10 FAST candidates) and DC
// (1000 pixels); no features, so FC, MO, DR and LSS do nothing.
#include <cstdint>
#include <string>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::arch {

inline std::vector<trace::TaskRecord> hand_task_rows() {
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
  std::vector<trace::TaskRecord> tasks = {
      task(Task::FD, Image::Left, 1000, 0),  task(Task::IF, Image::Left, 1000, 7),
      task(Task::FD, Image::Right, 1000, 0), task(Task::IF, Image::Right, 1000, 7),
      task(Task::DC, Image::Left, 1000, 3),  task(Task::LSS, Image::Left, 0, 21),
      task(Task::FC, Image::Left, 0, 31),    task(Task::FC, Image::Right, 0, 31),
      task(Task::MO, Image::Stereo, 0, 0),   task(Task::DR, Image::Stereo, 0, 11)};
  tasks[0].candidates = tasks[2].candidates = 10;
  tasks[9].search_range = 11;
  return tasks;
}

/// One registration frame of the hand rows: frontend 3 ms and backend 10 ms on the tracing
/// machine, with one backend kernel of `kernel_ms` (`kernel`; "projection": 100 map points, gemm
/// 3 x 100 x 4, accelerable).
inline trace::FrameTrace hand_frame(const std::string& kernel = "projection",
                                    std::int64_t kernel_ns = 6'000'000) {
  trace::FrameTrace f;
  f.frame.frame_id = 0;
  f.frame.sequence = "hand";
  f.frame.mode = trace::BackendMode::Registration;
  f.frame.frontend_host_ns = 3'000'000;
  f.frame.backend_host_ns = 10'000'000;
  f.tasks = hand_task_rows();
  trace::KernelRecord k;
  k.kernel = kernel;
  k.host_ns = kernel_ns;
  if (kernel == "projection") {
    k.accelerable = true;
    k.m = 100;
    k.ops = {trace::OpRecord{trace::Op::Gemm, 3, 100, 4, 0, 0}};
  }
  f.kernels = {k};
  return f;
}

/// The trace metadata of hand_frame(): its resolution and the tracing machine's suite times
/// (frontend 10 ms, backend 4 ms).
inline trace::TraceMeta hand_meta() {
  return {{"resolution", "40x25"},
          {"dataset", "hand"},
          {"precision", "fp64"},
          {"host_speed", R"({"suite": 1, "frontend_ms": 10.0, "backend_ms": 4.0, "samples": 1})"}};
}

}  // namespace edx::arch
