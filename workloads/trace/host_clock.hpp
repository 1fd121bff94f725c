#pragma once
// The host clocks of a trace (DESIGN.md: "host times are load-free (CPU time of the work)").
// A wall clock counts whatever else the machine runs while the work waits for a core; a CPU-time
// clock counts only the work, so a trace made on a busy machine records the same times as one
// made on a quiet one (test: tests/workloads/modes/host_time_load_test.cpp).
//
//   thread_cpu_ns(): CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID), in nanoseconds on
//                    Linux. Tasks, kernels and ops each run on one thread (OpenCV runs
//                    single-threaded while tracing unless --parallel; with --parallel, OpenCV
//                    calls nested in a task run serially on the task's thread). A frame's
//                    frontend total adds its concurrent chains' thread times to the caller's
//                    (frontend::FrameWorkClock); its backend total is the caller's
//                    (modes::run_backend_timed).
#include <cstdint>
#include <ctime>

namespace edx::trace {

namespace detail {
inline std::int64_t read_clock(clockid_t id) {
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}
}  // namespace detail

/// CPU time of the calling thread, ns (arbitrary origin: only differences mean something).
inline std::int64_t thread_cpu_ns() { return detail::read_clock(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace edx::trace
