#pragma once
// Cycles of a frontend task row on the accelerator (the trace's work counts, docs/TRACE.md tasks
// table) on the unit that serves its task (frontend_unit.hpp; each kind's formula is in its file
// under arch/frontend/units/ and in docs/MODEL.md), and the stream arithmetic the kinds share:
// stream(n, r) = ⌈n / r⌉.
#include <cstdint>

#include "arch/frontend/frontend_config.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

/// Bits of a pixel in the frontend's datapaths (8-bit grayscale).
inline constexpr int kPixelBits = 8;

/// Cycles to stream `pixels` at `per_cycle` pixels a cycle: ceil(pixels / per_cycle).
std::int64_t stream_cycles(std::int64_t pixels, double per_cycle);

/// Pixels a stencil of side `stencil` must have buffered before its first output on each level:
/// (stencil - 1) / 2 lines plus (stencil - 1) / 2 pixels (the window centred on the pixel).
inline std::int64_t stencil_halo_pixels(const trace::TaskRecord& task, int stencil) {
  const std::int64_t half = (stencil - 1) / 2;
  std::int64_t halo = 0;
  for (const trace::LevelWork& level : task.per_level) halo += half * level.width + half;
  return halo;
}

/// The stencil side a row used: the trace's window_size when it recorded one, else `configured`.
int stencil_of(const trace::TaskRecord& task, int configured);

/// Pixel lanes of a stream rate: ⌈pixels per cycle⌉ (a fractional rate reuses one lane).
int lanes_of(double pixels_per_cycle);

/// Bits of a k-row window of `columns` pixels held in flip-flops (an SB's shift register).
double window_bits(int rows, int columns);

/// The cycles of any task row on the unit of its task; level0_pixels is the image size (DR).
std::int64_t task_cycles(const trace::TaskRecord& task, std::int64_t level0_pixels,
                         const FrontendConfig& config);

}  // namespace edx::arch
