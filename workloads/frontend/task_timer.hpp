#pragma once
// Host timing of frontend tasks: the thread's CPU time (workloads/trace/host_clock.hpp) added to
// a TaskRecord's host_ns.
#include <cstdint>
#include <mutex>
#include <opencv2/core/utility.hpp>

#include "workloads/trace/host_clock.hpp"
#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// Adds the thread CPU time from construction to destruction to `task.host_ns`. A task that runs
/// in several stages (FD: detection, then selection once tracks are known) accumulates.
class ScopedTaskTimer {
 public:
  explicit ScopedTaskTimer(trace::TaskRecord& task)
      : task_(task), start_ns_(trace::thread_cpu_ns()) {}
  ~ScopedTaskTimer() { task_.host_ns += trace::thread_cpu_ns() - start_ns_; }
  ScopedTaskTimer(const ScopedTaskTimer&) = delete;
  ScopedTaskTimer& operator=(const ScopedTaskTimer&) = delete;

 private:
  trace::TaskRecord& task_;
  std::int64_t start_ns_;
};

/// While tracing with the tasks one after another (not `parallel_images`), OpenCV runs on the
/// calling thread only (cv::setNumThreads(1)), so that a task's thread CPU time is all of its
/// work rather than missing what OpenCV's pool threads did. With `parallel_images` the pool stays
/// (nested OpenCV calls run serially) and the object does nothing.
///
/// The setting is the process's, and cv::setNumThreads is not safe while another thread runs
/// OpenCV (with the TBB backend it rebuilds the arena under it: a sweep tracing two workload
/// points at once crashed in libtbb). So the holders are counted under a mutex: the first sets
/// one thread, the last brings the previous setting back, and no holder changes it in between.
class TracingThreads {
 public:
  explicit TracingThreads(bool parallel_images) : holds_(!parallel_images) {
    if (!holds_) return;
    State& s = state();
    const std::lock_guard<std::mutex> lock(s.mutex);
    if (s.holders++ == 0) {
      s.previous = cv::getNumThreads();
      cv::setNumThreads(1);
    }
  }
  ~TracingThreads() {
    if (!holds_) return;
    State& s = state();
    const std::lock_guard<std::mutex> lock(s.mutex);
    if (--s.holders == 0) cv::setNumThreads(s.previous);
  }
  TracingThreads(const TracingThreads&) = delete;
  TracingThreads& operator=(const TracingThreads&) = delete;

 private:
  struct State {
    std::mutex mutex;
    int holders = 0;
    int previous = 0;
  };
  static State& state() {
    static State s;
    return s;
  }
  bool holds_;
};

/// A TaskRecord for `task` on `image` with every count at 0.
inline trace::TaskRecord make_task(trace::Task task, trace::Image image) {
  trace::TaskRecord record;
  record.task = task;
  record.image = image;
  return record;
}

}  // namespace edx::frontend
