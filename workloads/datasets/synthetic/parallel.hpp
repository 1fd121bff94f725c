#pragma once
// A minimal parallel loop over [0, count) on `threads` std::threads (the caller's thread is one
// of them). Items are handed out dynamically; results must not depend on which thread ran an
// item (each item writes its own output), so output is deterministic.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace edx::synthetic {

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

}  // namespace edx::synthetic
