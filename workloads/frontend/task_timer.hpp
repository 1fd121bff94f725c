#pragma once
// Host timing of frontend tasks: steady-clock nanoseconds added to a TaskRecord's host_ns.
#include <chrono>
#include <cstdint>

#include "workloads/trace/records.hpp"

namespace edx::frontend {

/// Steady-clock time in nanoseconds (arbitrary epoch; only differences mean something).
inline std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// Adds the time from construction to destruction to `task.host_ns`. A task that runs in
/// several stages (FD: detection, then selection once tracks are known) accumulates.
class ScopedTaskTimer {
 public:
  explicit ScopedTaskTimer(trace::TaskRecord& task) : task_(task), start_ns_(steady_now_ns()) {}
  ~ScopedTaskTimer() { task_.host_ns += steady_now_ns() - start_ns_; }
  ScopedTaskTimer(const ScopedTaskTimer&) = delete;
  ScopedTaskTimer& operator=(const ScopedTaskTimer&) = delete;

 private:
  trace::TaskRecord& task_;
  std::int64_t start_ns_;
};

/// A TaskRecord for `task` on `image` with every count at 0.
inline trace::TaskRecord make_task(trace::Task task, trace::Image image) {
  trace::TaskRecord record;
  record.task = task;
  record.image = image;
  return record;
}

}  // namespace edx::frontend
