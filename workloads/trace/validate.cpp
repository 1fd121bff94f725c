#include "workloads/trace/validate.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <tuple>

namespace edx::trace {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw std::runtime_error(fmt::format("{}: {}", where, what));
}

// `Where`: a callable giving the row's place ("FILE: frame 3, task 1 (FD)"), formatted only when
// a check fails (a trace has tens of thousands of rows, nearly always valid).

// Bounds no real run reaches, so that a corrupt value is named here instead of overflowing a
// model's arithmetic later (issue 21: a 9e18 ns kernel gave R^2 -9e24; sizes of 2e9 a negative
// BRAM count): a host time of 10^4 s, a count of 10^12, a matrix dimension of 10^7.
constexpr std::int64_t kMaxHostNs = 10'000'000'000'000;
constexpr std::int64_t kMaxCount = 1'000'000'000'000;
constexpr std::int64_t kMaxDimension = 10'000'000;

template <typename Where>
void require_non_negative(std::int64_t value, const char* name, const Where& where,
                          std::int64_t max = kMaxCount) {
  if (value < 0) fail(where(), fmt::format("{} is negative ({})", name, value));
  if (value > max) fail(where(), fmt::format("{} is {}, above the plausible {}", name, value, max));
}

template <typename Where>
void validate_pose(const std::optional<PoseArray>& pose, const char* name, const Where& where) {
  if (!pose) return;
  double norm2 = 0;
  for (std::size_t i = 0; i < pose->size(); ++i) {
    if (!std::isfinite((*pose)[i])) fail(where(), fmt::format("{} has a non-finite value", name));
    if (i >= 3) norm2 += (*pose)[i] * (*pose)[i];
  }
  if (std::abs(std::sqrt(norm2) - 1.0) > 1e-6) {
    fail(where(), fmt::format("{} quaternion norm is {:.9f}, expected 1", name, std::sqrt(norm2)));
  }
}

/// Whether `text` is a JSON object: valid JSON (nlohmann's parser, checking only) whose first
/// character past JSON whitespace opens an object.
bool is_json_object(const std::string& text) {
  if (text == "{}") return true;  // nearly every kernel's detail
  // nlohmann's parser skips a UTF-8 byte order mark first; so does this check.
  const std::size_t start = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
  const std::size_t first = text.find_first_not_of(" \t\n\r", start);
  return first != std::string::npos && text[first] == '{' && nlohmann::json::accept(text);
}

template <typename Where>
void validate_task(const TaskRecord& task, const Where& where) {
  const std::pair<std::int64_t, const char*> counts[] = {
      {task.host_ns, "host_ns"},         {task.pixels, "pixels"},
      {task.levels, "levels"},           {task.candidates, "candidates"},
      {task.keypoints, "keypoints"},     {task.descriptors, "descriptors"},
      {task.comparisons, "comparisons"}, {task.windows, "windows"},
      {task.window_size, "window_size"}, {task.search_range, "search_range"},
      {task.points, "points"},           {task.iterations, "iterations"}};
  for (const auto& [value, name] : counts) {
    require_non_negative(value, name, where,
                         name == std::string_view("host_ns") ? kMaxHostNs : kMaxCount);
  }
  if (task.per_level.empty()) return;
  std::int64_t pixels = 0;
  for (const LevelWork& level : task.per_level) {
    if (level.level < 0 || level.width < 0 || level.height < 0 || level.pixels < 0 ||
        level.points < 0 || level.iterations < 0) {
      fail(where(), fmt::format("per_level entry {} has a negative value", level.level));
    }
    pixels += level.pixels;
  }
  if (pixels != task.pixels) {
    fail(where(), fmt::format("per_level pixels sum to {}, task says {}", pixels, task.pixels));
  }
}

template <typename Where>
void validate_kernel(const KernelRecord& kernel, const Where& where) {
  if (kernel.kernel.empty()) fail(where(), "kernel name is empty");
  require_non_negative(kernel.host_ns, "host_ns", where, kMaxHostNs);
  require_non_negative(kernel.m, "m", where, kMaxDimension);
  require_non_negative(kernel.n, "n", where, kMaxDimension);
  require_non_negative(kernel.k, "k", where, kMaxDimension);
  if (!is_json_object(kernel.detail_json)) {
    fail(where(), fmt::format("detail is not a JSON object: '{}'", kernel.detail_json));
  }
  for (std::size_t i = 0; i < kernel.ops.size(); ++i) {
    const OpRecord& op = kernel.ops[i];
    const auto op_where = [&] { return fmt::format("{}, op {}", where(), i); };
    require_non_negative(op.m, "m", op_where, kMaxDimension);
    require_non_negative(op.n, "n", op_where, kMaxDimension);
    require_non_negative(op.k, "k", op_where, kMaxDimension);
    require_non_negative(op.host_ns, "host_ns", op_where, kMaxHostNs);
    for (const auto& [rows, cols, name] :
         {std::tuple{op.m, op.n, "m x n"}, std::tuple{op.m, op.k, "m x k"},
          std::tuple{op.n, op.k, "n x k"}}) {
      if (rows * cols > kMaxOperandElements) {  // each <= 10^7: the product fits 64 bits
        fail(op_where(), fmt::format("an operand of {} = {} x {} elements, above the 2^32 no "
                                     "host holds",
                                     name, rows, cols));
      }
    }
    if (op.batch < 1) fail(op_where(), fmt::format("batch must be at least 1, is {}", op.batch));
    require_non_negative(op.batch, "batch", op_where, kMaxDimension);
    if ((op.flags & ~op_flags::kAll) != 0) {
      fail(op_where(), fmt::format("unknown flag bits 0x{:x}", op.flags & ~op_flags::kAll));
    }
  }
}

}  // namespace

std::optional<ImageSize> parse_image_size(const std::string& resolution) {
  ImageSize size;
  char x = 0, extra = 0;
  if (std::sscanf(resolution.c_str(), "%" SCNd64 "%c%" SCNd64 "%c", &size.width, &x, &size.height,
                  &extra) != 3 ||
      x != 'x' || size.width < 1 || size.height < 1 || size.width > 65536 || size.height > 65536) {
    return std::nullopt;
  }
  return size;
}

void validate_frame(const FrameTrace& trace, const std::string& where, const ImageSize& image) {
  validate_frame(trace, where);
  const std::int64_t pyramid = kMaxLevels * image.width * image.height;  // <= 2^38
  const std::int64_t side = std::max(image.width, image.height);
  // The bounds' wording, made only for a failing check.
  const auto levels = [] { return fmt::format("the {} levels a pyramid has", kMaxLevels); };
  const auto pixels = [&] {
    return fmt::format("the {} pixels of a {}-level pyramid of the {}x{} images (meta.resolution)",
                       pyramid, kMaxLevels, image.width, image.height);
  };
  const auto longer = [&] { return fmt::format("the {} pixels of the images' longer side", side); };
  for (std::size_t i = 0; i < trace.tasks.size(); ++i) {
    const TaskRecord& task = trace.tasks[i];
    const auto cap = [&](std::int64_t value, const char* name, std::int64_t max, const auto& what) {
      if (value <= max) return;
      fail(fmt::format("{}: frame {}, task {} ({})", where, trace.frame.frame_id, i,
                       to_string(task.task)),
           fmt::format("{} is {}, more than {}", name, value, what()));
    };
    cap(task.levels, "levels", kMaxLevels, levels);
    cap(static_cast<std::int64_t>(task.per_level.size()), "per_level's length", kMaxLevels, levels);
    for (const auto& [value, name] :
         {std::pair{task.pixels, "pixels"}, std::pair{task.candidates, "candidates"},
          std::pair{task.keypoints, "keypoints"}, std::pair{task.descriptors, "descriptors"},
          std::pair{task.points, "points"}, std::pair{task.windows, "windows"}}) {
      cap(value, name, pyramid, pixels);
    }
    cap(task.window_size, "window_size", side, longer);
    cap(task.search_range, "search_range", side, longer);
  }
}

void validate_frame(const FrameTrace& trace, const std::string& where) {
  const FrameRecord& frame = trace.frame;
  const auto frame_where = [&] { return fmt::format("{}: frame {}", where, frame.frame_id); };
  require_non_negative(frame.frame_id, "frame_id", frame_where);
  require_non_negative(frame.frontend_host_ns, "frontend_host_ns", frame_where, kMaxHostNs);
  require_non_negative(frame.backend_host_ns, "backend_host_ns", frame_where, kMaxHostNs);
  if (frame.sequence.empty()) fail(frame_where(), "sequence is empty");
  if (frame.backend_status.empty()) fail(frame_where(), "backend_status is empty");
  if (frame.mode != BackendMode::None && frame.estimated_pose == std::nullopt &&
      frame.backend_status == "ok") {
    fail(frame_where(), "backend ran with status ok but recorded no estimated pose");
  }
  validate_pose(frame.estimated_pose, "estimated pose", frame_where);
  validate_pose(frame.ground_truth_pose, "ground-truth pose", frame_where);
  for (std::size_t i = 0; i < trace.tasks.size(); ++i) {
    validate_task(trace.tasks[i], [&] {
      return fmt::format("{}, task {} ({})", frame_where(), i, to_string(trace.tasks[i].task));
    });
  }
  for (std::size_t i = 0; i < trace.kernels.size(); ++i) {
    validate_kernel(trace.kernels[i], [&] {
      return fmt::format("{}, kernel {} ({})", frame_where(), i, trace.kernels[i].kernel);
    });
  }
}

}  // namespace edx::trace
