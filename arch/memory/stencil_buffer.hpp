#pragma once
// The stencil buffer (SB) of the paper's Sec. V-C, Fig. 11: a chain of cascaded line FIFOs
// feeding one shift register per stencil consumer, and the SB optimization rule of Fig. 12
// (replicate a pixel into two SBs and re-read it from DRAM instead of keeping it on chip
// between two distant consumers).
//
// Sizing (Sec. V-C, "Basic Stencil Buffer Design"): an SB serving consumers of h_c x w_c windows
// over lines of W pixels of b bytes holds
//   lines            L = max_c h_c                  (one cascaded FIFO per buffered line)
//   FIFO bytes       L * W * b                      (each FIFO holds one line of W pixels)
//   shift registers  h_c * w_c pixels for consumer c (flip-flops, not BRAM)
// FIFO i (0 = the first, fed by the input) writes into the shift register of consumer c iff
// i < h_c: in the paper's example (4x3 and 3x3) FIFOs 0..2 feed both registers and FIFO 3 only
// the 4x3 one. Each FIFO is one memory structure of 8*b bits x W words (the platform's memory
// kind maps it onto blocks).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/memory/bram.hpp"

namespace edx::arch {

/// One stencil operation reading the SB: a `height` x `width` window.
struct StencilShape {
  std::string name;
  int height = 3;
  int width = 3;
};

/// What an SB must serve.
struct StencilBufferSpec {
  std::string name = "sb";
  std::int64_t line_width_pixels = 640;  ///< W, pixels per image line
  int bytes_per_pixel = 1;               ///< b (8-bit grayscale)
  std::vector<StencilShape> consumers;   ///< at least one

  /// Throws std::runtime_error naming the SB and the bad field (or consumer).
  void validate() const;
  nlohmann::json to_json() const;
};

/// The sized SB.
struct StencilBuffer {
  StencilBufferSpec spec;
  int lines = 0;                                    ///< L = max_c h_c cascaded FIFOs
  std::int64_t fifo_depth_pixels = 0;               ///< W pixels per FIFO
  std::int64_t fifo_bytes = 0;                      ///< L * W * b
  std::vector<std::int64_t> shift_register_pixels;  ///< h_c * w_c per consumer
  std::int64_t shift_register_bytes = 0;            ///< sum_c h_c * w_c * b
  /// feeds[i] lists the consumer indices whose shift register FIFO i writes into (i < h_c).
  std::vector<std::vector<int>> feeds;

  /// Its memories: L line FIFOs, each 8*b bits x W words (one MemoryStructure, count L).
  std::vector<MemoryStructure> memory_structures() const;
  nlohmann::json to_json() const;
};

/// Sizes the SB of `spec` (validated first).
StencilBuffer size_stencil_buffer(const StencilBufferSpec& spec);

// ---- SB optimization (Sec. V-C, "Reducing SB Sizes by Redundant DRAM Accesses", Fig. 12) ----

/// One pixel read at cycle p1 and consumed by two stencil operations at c1 <= c2; p2 is the cycle
/// at which it would be read again from DRAM for the second consumer.
struct SbSharingInput {
  std::int64_t p1 = 0;
  std::int64_t c1 = 0;
  std::int64_t c2 = 0;
  std::int64_t p2 = 0;
  std::int64_t image_pixels = 0;  ///< pixels re-read per frame when replicating
  int bytes_per_pixel = 1;
  /// Throws std::runtime_error unless p1 <= c1 <= c2, p2 <= c2, image_pixels >= 0, b >= 1.
  void validate() const;
};

/// Both SB sizes and the decision.
struct SbSharingDecision {
  std::int64_t shared_pixels = 0;               ///< one SB: max(c1, c2) - p1
  std::int64_t replicated_pixels = 0;           ///< two SBs: (c1 - p1) + (c2 - p2)
  bool replicate = false;                       ///< p2 > c1 and replicated < shared
  std::int64_t saved_pixels = 0;                ///< shared - replicated when replicating, else 0
  std::int64_t extra_dram_bytes_per_frame = 0;  ///< image_pixels * b when replicating, else 0
  nlohmann::json to_json() const;
};

/// The rule of Sec. V-C: one pixel enters the SB per cycle, so the SB holding a pixel from p1
/// until its last use c2 needs max(c1, c2) - p1 pixels; re-reading it at p2 for the second
/// consumer needs (c1 - p1) + (c2 - p2). Replicate iff p2 > c1 (the first copy is dead before the
/// second is read) and that total is smaller; the price is one more DRAM read of the image.
SbSharingDecision decide_sb_sharing(const SbSharingInput& input);

/// A pixel stream: pixel i (0 <= i < N) is produced or consumed at cycle
///   t(i) = first_cycle + i * cycles / pixels      (rate = pixels / cycles pixels per cycle).
/// The rate is a fraction so that lifetimes are exact.
struct PixelStream {
  std::int64_t first_cycle = 0;
  std::int64_t pixels = 1;  ///< numerator of the rate
  std::int64_t cycles = 1;  ///< denominator of the rate
  double rate() const { return static_cast<double>(pixels) / static_cast<double>(cycles); }
};

/// An exact non-negative rational number of cycles.
struct Cycles {
  std::int64_t numerator = 0;
  std::int64_t denominator = 1;
  double value() const { return static_cast<double>(numerator) / static_cast<double>(denominator); }
  /// Smallest integer >= the value.
  std::int64_t ceil() const;
};

/// max over 0 <= i < n of consumer(i) - producer(i), exactly. The difference is linear in i,
///   d(i) = (c0 - p0) + i * (cc / cp - pc / pp),
/// so the maximum is at i = 0 or i = n - 1. Throws std::runtime_error when some pixel would be
/// consumed before it is produced (d(i) < 0 at an end) or a stream rate is not positive.
Cycles max_lifetime(const PixelStream& producer, const PixelStream& consumer, std::int64_t n);

/// Streams version of the rule for an image of `n` pixels: the first read `p1` feeds consumers
/// `c1` and `c2`; `p2` is the re-read. Sizes in pixels are lifetimes x the producer's rate,
/// rounded up:
///   shared     = ceil(max(maxlife(p1, c1), maxlife(p1, c2)) * rate(p1))
///   replicated = ceil(maxlife(p1, c1) * rate(p1)) + ceil(maxlife(p2, c2) * rate(p2))
/// Replicate iff p2(i) > c1(i) for every pixel (checked at both ends: linear) and replicated <
/// shared; extra DRAM bytes = n * bytes_per_pixel. With unit rates and n = 1 this is
/// decide_sb_sharing().
SbSharingDecision decide_sb_sharing(const PixelStream& p1, const PixelStream& c1,
                                    const PixelStream& c2, const PixelStream& p2, std::int64_t n,
                                    int bytes_per_pixel);

}  // namespace edx::arch
