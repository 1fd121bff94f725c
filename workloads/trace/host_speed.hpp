#pragma once
// How fast the machine that made a trace is (DESIGN.md: "meta records how fast the tracing machine
// is on a fixed reference suite"; docs/TRACE.md, "Host speed"). The suite itself runs in
// workloads/modes/host_speed_meter.hpp; the trace carries its result as the JSON meta value
// `host_speed`, e.g.
//   {"suite": 1, "frontend_ms": 61.2, "backend_ms": 9.8, "samples": 12, "inputs": "9c0f…"}
// and arch maps trace host times to a platform's host through the ratio of the two machines'
// suite times (arch/host/host_model.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::trace {

/// The version of the reference suite this build runs. Any change of the suite's work (inputs,
/// options, kernels, sizes) bumps it: suite times of different versions are not comparable.
inline constexpr int kHostSpeedSuite = 1;

struct HostSpeed {
  int suite = kHostSpeedSuite;
  double frontend_ms = 0;  ///< median thread CPU ms of one pass of the suite's frontend part
  double backend_ms = 0;   ///< median thread CPU ms of one pass of its backend part
  int samples = 0;         ///< passes the medians are over
  std::string inputs;      ///< FNV-1a of the suite's generated images (same on every machine)
  /// Every sample, in order: frames traced before it (0 for the initial samples, the frame
  /// count for the final ones) and the two parts' CPU ms. Empty when only medians are known.
  std::vector<std::int64_t> sample_frames;
  std::vector<double> frontend_samples_ms, backend_samples_ms;
  bool operator==(const HostSpeed&) const = default;
};

/// Median of samples (the mean of the middle two for an even count); throws
/// std::invalid_argument when there are none.
double median_of(std::vector<double> samples);

/// The meta value (compact JSON).
std::string to_meta_value(const HostSpeed& speed);

/// Parses meta `host_speed` of the trace `file`; throws std::runtime_error naming the file and
/// the key when it is missing or malformed (times must be > 0, suite >= 1, sample positions
/// non-negative and non-decreasing).
HostSpeed host_speed_of(const TraceMeta& meta, const std::string& file);

}  // namespace edx::trace
