// common::parallel_for and common::run_jobs: every item runs once whatever the threads, and an
// error is the one the jobs run in order would give, not the first to finish.
#include "common/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace edx::common {
namespace {

TEST(Parallel, EveryItemRunsOnceOnAnyNumberOfThreads) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<int> runs(100, 0);
    parallel_for(100, threads, [&](int i) { ++runs[static_cast<std::size_t>(i)]; });
    EXPECT_EQ(runs, std::vector<int>(100, 1)) << threads;
  }
}

TEST(Parallel, JobsAllRunAndTheFirstJobsErrorInListOrderIsRethrown) {
  // Job 1 throws late, job 2 at once: on two threads job 2 finishes first, yet job 1's error is
  // the one seen (as when the jobs run one after another), and job 3 still ran.
  for (int threads : {1, 2, 4}) {
    std::atomic<int> ran{0};
    const std::vector<std::function<void()>> jobs = {
        [&] { ++ran; },
        [&] {
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
          ++ran;
          throw std::runtime_error("job 1");
        },
        [&] {
          ++ran;
          throw std::invalid_argument("job 2");
        },
        [&] { ++ran; }};
    try {
      run_jobs(jobs, threads);
      ADD_FAILURE() << "no error with " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "job 1") << threads;
    }
    EXPECT_EQ(ran.load(), 4) << threads;
  }
}

TEST(Parallel, JobsWithoutErrorsReturnNormally) {
  int a = 0, b = 0;
  run_jobs({[&] { a = 1; }, [&] { b = 2; }}, 2);
  EXPECT_EQ(a + b, 3);
  run_jobs({}, 2);  // nothing to run
}

}  // namespace
}  // namespace edx::common
