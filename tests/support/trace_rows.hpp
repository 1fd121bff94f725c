#pragma once
// A trace's rows of work: what two tracings of the same work must agree on.
#include <string>
#include <vector>

#include "workloads/trace/records.hpp"

namespace edx::testing {

/// A trace's records without their host times (the only fields two tracings of the same work
/// may differ in).
inline std::vector<trace::FrameTrace> without_host_times(std::vector<trace::FrameTrace> frames) {
  for (trace::FrameTrace& f : frames) {
    f.frame.frontend_host_ns = f.frame.backend_host_ns = 0;
    for (trace::TaskRecord& t : f.tasks) t.host_ns = 0;
    for (trace::KernelRecord& k : f.kernels) {
      k.host_ns = 0;
      for (trace::OpRecord& op : k.ops) op.host_ns = 0;
    }
  }
  return frames;
}

/// A trace's meta without what differs between two tracings of the same work: when
/// (created_utc), how fast the host was (host_speed) and which build traced it (source_revision).
inline trace::TraceMeta without_host_meta(trace::TraceMeta meta) {
  for (const char* key : {"created_utc", "host_speed", "source_revision"}) meta.erase(key);
  return meta;
}

}  // namespace edx::testing
