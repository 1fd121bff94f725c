#pragma once
// Checks that a recorded frame obeys the trace contract (docs/TRACE.md). Shared by the writer
// (refuses to write a bad frame) and the reader (refuses to hand one over).
#include <cstdint>
#include <optional>
#include <string>

#include "workloads/trace/records.hpp"

namespace edx::trace {

/// Throws std::runtime_error "<where>: <what is wrong>" on the first violation: negative counts
/// or times, per-level rows that do not add up, op flags outside the known set, empty kernel
/// names, detail text that is not a JSON object, poses with a non-unit quaternion.
void validate_frame(const FrameTrace& frame, const std::string& where);

/// The level-0 image of a trace's frames (meta.resolution).
struct ImageSize {
  std::int64_t width = 0;
  std::int64_t height = 0;
};
/// meta.resolution "WxH" with both sides in [1, 65536] (the dataset readers' limit), or nullopt
/// when it is not one (the frontend model names a bad resolution when it needs one).
std::optional<ImageSize> parse_image_size(const std::string& resolution);

/// The same checks, and the frame's work against its images (issue 45, docs/RELIABILITY.md
/// "Input limits"): at most kMaxLevels pyramid levels a task; pixels, candidates, keypoints,
/// descriptors, tracked points and refinement windows of a task at most the pixels of such a
/// pyramid of the image, kMaxLevels x W x H (each is a pixel of one level, and a level is no
/// larger than the image); a window side or search range at most the image's longer side.
void validate_frame(const FrameTrace& frame, const std::string& where, const ImageSize& image);

/// The most pyramid levels a task may record: an image pyramid scaled by ORB's 1.2 a level goes
/// from 65536 pixels (the widest image) to one in 61 levels; halving pyramids take 16.
inline constexpr std::int64_t kMaxLevels = 64;
/// The most elements of one dense operand of an op (m x n, m x k, n x k): 2^32, 32 GiB in
/// double, more than the memory of any host edx models (4 to 16 GiB), so no run has it.
inline constexpr std::int64_t kMaxOperandElements = std::int64_t{1} << 32;

}  // namespace edx::trace
