#pragma once
// A trace's frames repeated in order to N frames, renumbered, with increasing time stamps (the
// `system` and `sweep` benchmarks time 2000-frame traces made from short real ones).
#include <cstdint>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::bench {

inline std::vector<trace::FrameTrace> stretch_trace(const std::vector<trace::FrameTrace>& source,
                                                    std::size_t n) {
  std::vector<trace::FrameTrace> frames;
  if (source.empty()) return frames;
  frames.reserve(n);
  const std::int64_t span =
      source.back().frame.timestamp_ns - source.front().frame.timestamp_ns + 50'000'000;
  for (std::size_t i = 0; i < n; ++i) {
    trace::FrameTrace f = source[i % source.size()];
    f.frame.frame_id = static_cast<std::int64_t>(i);
    f.frame.timestamp_ns += static_cast<std::int64_t>(i / source.size()) * span;
    frames.push_back(std::move(f));
  }
  return frames;
}

}  // namespace edx::bench
