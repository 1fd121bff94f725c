// frontend::TracingThreads: OpenCV on one thread while any tracer holds it, the process's
// previous setting back when the last lets go, whatever the threads and nesting.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>
#include <vector>

#include "workloads/frontend/task_timer.hpp"

namespace edx::frontend {
namespace {

TEST(TracingThreads, TheFirstHolderSetsOneThreadAndTheLastRestores) {
  cv::setNumThreads(2);
  const int before = cv::getNumThreads();
  {
    const TracingThreads outer(false);
    EXPECT_EQ(cv::getNumThreads(), 1);
    { const TracingThreads inner(false); }
    EXPECT_EQ(cv::getNumThreads(), 1);  // the outer still holds it
    std::thread other([] { const TracingThreads held(false); });
    other.join();
    EXPECT_EQ(cv::getNumThreads(), 1);
  }
  EXPECT_EQ(cv::getNumThreads(), before);
  {
    const TracingThreads parallel(true);  // parallel images keep the pool
    EXPECT_EQ(cv::getNumThreads(), before);
  }
  EXPECT_EQ(cv::getNumThreads(), before);
}

// Tracers on several threads at once, each running OpenCV while it holds: the setting changes
// only when no tracer runs (this crashed in libtbb when each holder set and restored it).
TEST(TracingThreads, ConcurrentTracersRunOpenCvSafely) {
  const int before = cv::getNumThreads();
  std::vector<std::thread> workers;
  for (int w = 0; w < 4; ++w) {
    workers.emplace_back([w] {
      for (int i = 0; i < 50; ++i) {
        const TracingThreads held(false);
        cv::Mat image(64, 64, CV_8UC1, cv::Scalar(w + i));
        cv::Mat blurred;
        cv::blur(image, blurred, cv::Size(3, 3));
        EXPECT_EQ(blurred.at<unsigned char>(32, 32), static_cast<unsigned char>(w + i));
      }
    });
  }
  for (std::thread& t : workers) t.join();
  EXPECT_EQ(cv::getNumThreads(), before);
}

}  // namespace
}  // namespace edx::frontend
