#include "arch/frontend/task_timing.hpp"

#include <algorithm>
#include <cmath>

namespace edx::arch {

std::int64_t stream_cycles(std::int64_t pixels, double per_cycle) {
  return static_cast<std::int64_t>(std::ceil(static_cast<double>(pixels) / per_cycle - 1e-9));
}

int stencil_of(const trace::TaskRecord& task, int configured) {
  return task.window_size > 0 ? static_cast<int>(task.window_size) : configured;
}

int lanes_of(double pixels_per_cycle) {
  return std::max(1, static_cast<int>(std::ceil(pixels_per_cycle - 1e-9)));
}

double window_bits(int rows, int columns) { return double(rows) * columns * kPixelBits; }

std::int64_t task_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                         const FrontendConfig& config) {
  return config.unit(task.task).unit->cycles(task, level0_pixels, config);
}

}  // namespace edx::arch
