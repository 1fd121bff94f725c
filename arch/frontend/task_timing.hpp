#pragma once
// Cycles of each frontend task on the accelerator, from the work counts the trace recorded
// (docs/TRACE.md, tasks table) and the configured datapath (FrontendConfig). Every formula is
// listed in docs/MODEL.md with its source; stream(n, r) = ceil(n / r).
#include <cstdint>

#include "arch/frontend/frontend_config.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// Cycles to stream `pixels` at `per_cycle` pixels a cycle: ceil(pixels / per_cycle).
std::int64_t stream_cycles(std::int64_t pixels, double per_cycle);

/// Pixels a stencil of side `stencil` must have buffered before its first output on each level:
/// (stencil - 1) / 2 lines plus (stencil - 1) / 2 pixels (the window centred on the pixel).
std::int64_t stencil_halo_pixels(const trace::TaskRecord& task, int stencil);

/// FD: the FAST segment test streams the pyramid, fe_pixels_per_cycle pixels a cycle, after the
/// halo of its 7x7 window fills: stream(pixels + halo, r_fe).
std::int64_t fd_cycles(const trace::TaskRecord& task, const FrontendConfig& config);
/// IF: the Gaussian stencil over the same pyramid: stream(pixels + halo, r_fe).
std::int64_t if_cycles(const trace::TaskRecord& task, const FrontendConfig& config);
/// FC per descriptor: orientation by intensity moments over the patch, one patch row per
/// cycle group (ceil(patch / rows_per_cycle)), then 256 rBRIEF tests, fc_tests_per_cycle a
/// cycle: descriptors * (ceil(p / rows) + ceil(256 / tests)).
std::int64_t fc_cycles(const trace::TaskRecord& task, const FrontendConfig& config);
/// MO: one 256-bit Hamming distance per comparator a cycle: ceil(comparisons / comparators).
std::int64_t mo_cycles(const trace::TaskRecord& task, const FrontendConfig& config);
/// DR: both images' level 0 stream through DR's stencil buffers at dr_pixels_per_cycle each (in
/// parallel), while the SADs of each window's search_range offsets run dr_sad_units at a time,
/// one window row a cycle: max(stream(W*H, r_dr), windows * ceil(search / units) * window).
std::int64_t dr_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                       const FrontendConfig& config);
/// DC: the Scharr stencil over the LK pyramid: stream(pixels + halo, r_dc).
std::int64_t dc_cycles(const trace::TaskRecord& task, const FrontendConfig& config);
/// LSS: each Gauss-Newton update of a point accumulates the 2x2 normal equations and the
/// mismatch vector over the window (5 products a pixel: Ix², IxIy, Iy², IxIt, IyIt) plus the
/// bilinear interpolation of the moved window (4 products a pixel), and each point solve first
/// accumulates the window's gradient matrix once (3 products a pixel):
/// ceil(window² (9 iterations + 3 points) / macs).
std::int64_t lss_cycles(const trace::TaskRecord& task, const FrontendConfig& config);

/// The cycles of any task row; level0_pixels is the image size (for DR).
std::int64_t task_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                         const FrontendConfig& config);

}  // namespace edx::arch
