#pragma once
// Checks that a recorded frame obeys the trace contract (docs/TRACE.md). Shared by the writer
// (refuses to write a bad frame) and the reader (refuses to hand one over).
#include <string>

#include "workloads/trace/records.hpp"

namespace edx::trace {

/// Throws std::runtime_error "<where>: <what is wrong>" on the first violation: negative counts
/// or times, per-level rows that do not add up, op flags outside the known set, empty kernel
/// names, detail text that is not a JSON object, poses with a non-unit quaternion.
void validate_frame(const FrameTrace& frame, const std::string& where);

}  // namespace edx::trace
