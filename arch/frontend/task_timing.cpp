#include "arch/frontend/task_timing.hpp"

#include <algorithm>
#include <cmath>

namespace edx::arch {
namespace {

std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return (a + b - 1) / b; }

/// rBRIEF compares 256 pixel pairs per descriptor (Rublee et al. 2011).
constexpr std::int64_t kBriefTests = 256;
/// LK products per pixel and Gauss-Newton update: 5 for the normal equations and mismatch,
/// 4 for bilinear interpolation of the moved window (Bouguet 2001, OpenCV's LK).
constexpr std::int64_t kLkProductsPerIteration = 9;
/// LK products per pixel once per point solve: the 2x2 gradient matrix Ix², IxIy, Iy².
constexpr std::int64_t kLkProductsPerPoint = 3;

int stencil_of(const trace::TaskRecord& task, int configured) {
  return task.window_size > 0 ? static_cast<int>(task.window_size) : configured;
}

}  // namespace

std::int64_t stream_cycles(std::int64_t pixels, double per_cycle) {
  return static_cast<std::int64_t>(std::ceil(static_cast<double>(pixels) / per_cycle - 1e-9));
}

std::int64_t stencil_halo_pixels(const trace::TaskRecord& task, int stencil) {
  const std::int64_t half = (stencil - 1) / 2;
  std::int64_t halo = 0;
  for (const trace::LevelWork& level : task.per_level) halo += half * level.width + half;
  return halo;
}

std::int64_t fd_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  if (task.pixels == 0) return 0;
  return stream_cycles(task.pixels + stencil_halo_pixels(task, c.fd_stencil),
                       c.fe_pixels_per_cycle);
}

std::int64_t if_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  if (task.pixels == 0) return 0;
  return stream_cycles(task.pixels + stencil_halo_pixels(task, stencil_of(task, c.if_stencil)),
                       c.fe_pixels_per_cycle);
}

std::int64_t fc_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  const std::int64_t patch = stencil_of(task, c.fc_patch);
  const std::int64_t per_descriptor =
      ceil_div(patch, c.fc_patch_rows_per_cycle) + ceil_div(kBriefTests, c.fc_tests_per_cycle);
  return task.descriptors * per_descriptor;
}

std::int64_t mo_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  return ceil_div(task.comparisons, c.mo_comparators);
}

std::int64_t dr_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                       const FrontendConfig& c) {
  if (task.keypoints == 0 && task.windows == 0) return 0;
  const std::int64_t stream = stream_cycles(level0_pixels, c.dr_pixels_per_cycle);
  const std::int64_t sad = task.windows *
                           ceil_div(std::max<std::int64_t>(task.search_range, 1), c.dr_sad_units) *
                           std::max<std::int64_t>(task.window_size, 1);
  return std::max(stream, sad);
}

std::int64_t dc_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  if (task.pixels == 0) return 0;
  return stream_cycles(task.pixels + stencil_halo_pixels(task, c.dc_stencil),
                       c.dc_pixels_per_cycle);
}

std::int64_t lss_cycles(const trace::TaskRecord& task, const FrontendConfig& c) {
  const std::int64_t window = task.window_size * task.window_size;
  return ceil_div(
      window * (kLkProductsPerIteration * task.iterations + kLkProductsPerPoint * task.points),
      c.lss_macs_per_cycle);
}

std::int64_t task_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                         const FrontendConfig& c) {
  switch (task.task) {
    case trace::Task::FD:
      return fd_cycles(task, c);
    case trace::Task::IF:
      return if_cycles(task, c);
    case trace::Task::FC:
      return fc_cycles(task, c);
    case trace::Task::MO:
      return mo_cycles(task, c);
    case trace::Task::DR:
      return dr_cycles(task, level0_pixels, c);
    case trace::Task::DC:
      return dc_cycles(task, c);
    case trace::Task::LSS:
      return lss_cycles(task, c);
  }
  return 0;
}

}  // namespace edx::arch
