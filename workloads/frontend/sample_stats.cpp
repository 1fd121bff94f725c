#include "workloads/frontend/sample_stats.hpp"

#include "common/sample_set.hpp"

namespace edx::frontend {

SampleStats summarize(const std::vector<double>& values) {
  SampleStats s;
  s.count = values.size();
  if (values.empty()) return s;
  common::SampleSet set;
  set.reserve(values.size());
  for (const double value : values) set.add(value);
  s.mean = set.mean();
  s.sd = values.size() >= 2 ? set.sd() : 0.0;
  s.min = set.min();
  s.max = set.max();
  s.p50 = set.percentile(50);
  s.p99 = set.percentile(99);
  return s;
}

}  // namespace edx::frontend
