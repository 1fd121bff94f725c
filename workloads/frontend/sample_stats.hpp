#pragma once
// Summary statistics of a sample (per-frame task times, counts) as a plain struct for summaries
// and JSON; computed by common's SampleSet (one definition of SD and percentiles in edx).
#include <cstddef>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::frontend {

struct SampleStats {
  std::size_t count = 0;
  double mean = 0;
  double sd = 0;  ///< sample standard deviation sqrt(sum (x - mean)^2 / (n - 1)); 0 when n < 2
  double min = 0;
  double p50 = 0;  ///< percentiles: linear between closest ranks (numpy's default)
  double p99 = 0;
  double max = 0;
};

/// Statistics of `values` (all zero for an empty sample).
SampleStats summarize(const std::vector<double>& values);

/// Host-time statistics of one task row kind over the frames, in milliseconds.
struct TaskTimeSummary {
  trace::Task task = trace::Task::FD;
  trace::Image image = trace::Image::Left;
  SampleStats ms;
};

}  // namespace edx::frontend
