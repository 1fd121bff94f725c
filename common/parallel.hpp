#pragma once
// A minimal parallel loop over [0, count) on `threads` std::threads (the caller's thread is one
// of them). Items are handed out dynamically; results must not depend on which thread ran an
// item (each item writes its own output), so output is deterministic.
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace edx::common {

template <class Fn>
void parallel_for(int count, int threads, Fn&& fn) {
  threads = std::max(1, std::min(threads, count));
  if (threads == 1) {
    for (int i = 0; i < count; ++i) fn(i);
    return;
  }
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    try {
      for (int i = next.fetch_add(1); i < count; i = next.fetch_add(1)) fn(i);
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next.store(count);
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

/// Runs every job once on up to `threads` threads, all of them to the end, then rethrows the
/// exception of the first job (in the list's order) that threw: the error is the one a run of
/// the jobs one after another in that order would give, whichever thread finished first.
inline void run_jobs(const std::vector<std::function<void()>>& jobs, int threads) {
  std::vector<std::exception_ptr> errors(jobs.size());
  parallel_for(static_cast<int>(jobs.size()), threads, [&](int i) {
    try {
      jobs[static_cast<std::size_t>(i)]();
    } catch (...) {
      errors[static_cast<std::size_t>(i)] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

}  // namespace edx::common
