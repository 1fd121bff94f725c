#include "arch/memory/stencil_buffer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace edx::arch {
namespace {

using Wide = __int128;

std::int64_t narrow(Wide v, const char* what) {
  if (v > std::numeric_limits<std::int64_t>::max() ||
      v < std::numeric_limits<std::int64_t>::min()) {
    throw std::runtime_error(fmt::format("SB optimization: {} overflows 64 bits", what));
  }
  return static_cast<std::int64_t>(v);
}

/// ceil(a / b) for a >= 0, b > 0.
Wide ceil_div(Wide a, Wide b) { return (a + b - 1) / b; }

/// Pixels a buffer needs to hold a lifetime of `life` cycles at `stream`'s rate:
/// ceil(life * pixels / cycles).
std::int64_t lifetime_pixels(const Cycles& life, const PixelStream& stream) {
  return narrow(
      ceil_div(Wide{life.numerator} * stream.pixels, Wide{life.denominator} * stream.cycles),
      "lifetime in pixels");
}

void require_stream(const PixelStream& s, const char* which) {
  if (s.pixels <= 0 || s.cycles <= 0) {
    throw std::runtime_error(fmt::format(
        "SB optimization: stream {}: expected a rate pixels/cycles with both > 0, got {}/{}", which,
        s.pixels, s.cycles));
  }
}

/// Cycle of pixel i of `s` times denominator `den` (a multiple of s.pixels), exact.
Wide scaled_cycle(const PixelStream& s, std::int64_t i, Wide den) {
  return Wide{s.first_cycle} * den + Wide{i} * s.cycles * (den / s.pixels);
}

}  // namespace

void StencilBufferSpec::validate() const {
  auto fail = [&](const std::string& field, const std::string& expected) {
    throw std::runtime_error(
        fmt::format("stencil buffer '{}': {}: expected {}", name, field, expected));
  };
  if (line_width_pixels < 1) fail("line_width_pixels", "a line width >= 1 pixel");
  if (bytes_per_pixel < 1 || bytes_per_pixel > 8) fail("bytes_per_pixel", "1 to 8");
  if (consumers.empty()) fail("consumers", "at least one stencil consumer");
  for (std::size_t c = 0; c < consumers.size(); ++c) {
    const StencilShape& s = consumers[c];
    const std::string field = fmt::format("consumers[{}] '{}'", c, s.name);
    if (s.height < 1) fail(field + ".height", "a window height >= 1");
    if (s.width < 1) fail(field + ".width", "a window width >= 1");
    if (s.width > line_width_pixels) fail(field + ".width", "a window no wider than the line");
  }
}

nlohmann::json StencilBufferSpec::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const StencilShape& s : consumers) {
    list.push_back({{"name", s.name}, {"height", s.height}, {"width", s.width}});
  }
  return {{"name", name},
          {"line_width_pixels", line_width_pixels},
          {"bytes_per_pixel", bytes_per_pixel},
          {"consumers", list}};
}

StencilBuffer size_stencil_buffer(const StencilBufferSpec& spec) {
  spec.validate();
  StencilBuffer sb;
  sb.spec = spec;
  // L = max_c h_c
  for (const StencilShape& s : spec.consumers) sb.lines = std::max(sb.lines, s.height);
  sb.fifo_depth_pixels = spec.line_width_pixels;
  sb.fifo_bytes = std::int64_t{sb.lines} * spec.line_width_pixels * spec.bytes_per_pixel;
  for (const StencilShape& s : spec.consumers) {
    const std::int64_t pixels = std::int64_t{s.height} * s.width;  // h_c * w_c
    sb.shift_register_pixels.push_back(pixels);
    sb.shift_register_bytes += pixels * spec.bytes_per_pixel;
  }
  sb.feeds.resize(static_cast<std::size_t>(sb.lines));
  for (int i = 0; i < sb.lines; ++i) {
    for (std::size_t c = 0; c < spec.consumers.size(); ++c) {
      if (i < spec.consumers[c].height) sb.feeds[static_cast<std::size_t>(i)].push_back(int(c));
    }
  }
  return sb;
}

std::vector<MemoryStructure> StencilBuffer::memory_structures() const {
  return {MemoryStructure{spec.name + ".line_fifo", 8 * std::int64_t{spec.bytes_per_pixel},
                          fifo_depth_pixels, lines}};
}

nlohmann::json StencilBuffer::to_json() const {
  return {{"spec", spec.to_json()},
          {"lines", lines},
          {"fifo_depth_pixels", fifo_depth_pixels},
          {"fifo_bytes", fifo_bytes},
          {"shift_register_pixels", shift_register_pixels},
          {"shift_register_bytes", shift_register_bytes},
          {"feeds", feeds}};
}

void SbSharingInput::validate() const {
  auto fail = [](const std::string& message) {
    throw std::runtime_error("SB optimization: " + message);
  };
  if (c1 < p1) fail(fmt::format("c1: expected c1 >= p1, got c1 = {} < p1 = {}", c1, p1));
  if (c2 < c1) fail(fmt::format("c2: expected c1 <= c2, got c1 = {} > c2 = {}", c1, c2));
  if (c2 < p2) fail(fmt::format("p2: expected p2 <= c2, got p2 = {} > c2 = {}", p2, c2));
  if (image_pixels < 0) fail(fmt::format("image_pixels: expected >= 0, got {}", image_pixels));
  if (bytes_per_pixel < 1) {
    fail(fmt::format("bytes_per_pixel: expected >= 1, got {}", bytes_per_pixel));
  }
}

nlohmann::json SbSharingDecision::to_json() const {
  return {{"shared_pixels", shared_pixels},
          {"replicated_pixels", replicated_pixels},
          {"replicate", replicate},
          {"saved_pixels", saved_pixels},
          {"extra_dram_bytes_per_frame", extra_dram_bytes_per_frame}};
}

namespace {

SbSharingDecision decide(std::int64_t shared, std::int64_t replicated, bool reread_after_c1,
                         std::int64_t image_pixels, int bytes_per_pixel) {
  SbSharingDecision d;
  d.shared_pixels = shared;
  d.replicated_pixels = replicated;
  d.replicate = reread_after_c1 && replicated < shared;
  if (d.replicate) {
    d.saved_pixels = shared - replicated;
    d.extra_dram_bytes_per_frame = image_pixels * bytes_per_pixel;
  }
  return d;
}

}  // namespace

SbSharingDecision decide_sb_sharing(const SbSharingInput& in) {
  in.validate();
  const std::int64_t shared = std::max(in.c1, in.c2) - in.p1;         // max(C1, C2) - P1
  const std::int64_t replicated = (in.c1 - in.p1) + (in.c2 - in.p2);  // (C1-P1) + (C2-P2)
  return decide(shared, replicated, in.p2 > in.c1, in.image_pixels, in.bytes_per_pixel);
}

std::int64_t Cycles::ceil() const {
  return narrow(ceil_div(Wide{numerator}, Wide{denominator}), "cycles");
}

/// consumer(i) - producer(i) at i = 0 and i = n - 1, both scaled by den = pp * cp.
struct EndDifferences {
  Wide first = 0;
  Wide last = 0;
  Wide den = 1;
};

EndDifferences end_differences(const PixelStream& producer, const PixelStream& consumer,
                               std::int64_t n) {
  require_stream(producer, "producer");
  require_stream(consumer, "consumer");
  if (n < 1) throw std::runtime_error(fmt::format("SB optimization: n: expected >= 1, got {}", n));
  EndDifferences e;
  e.den = Wide{producer.pixels} * consumer.pixels;  // t(i) * den is an integer for both streams
  e.first = scaled_cycle(consumer, 0, e.den) - scaled_cycle(producer, 0, e.den);
  e.last = scaled_cycle(consumer, n - 1, e.den) - scaled_cycle(producer, n - 1, e.den);
  return e;
}

Cycles max_lifetime(const PixelStream& producer, const PixelStream& consumer, std::int64_t n) {
  const EndDifferences e = end_differences(producer, consumer, n);
  if (e.first < 0 || e.last < 0) {
    throw std::runtime_error(fmt::format(
        "SB optimization: pixel {} would be consumed before it is produced (consumer starts at "
        "cycle {}, producer at {})",
        e.first < 0 ? 0 : n - 1, consumer.first_cycle, producer.first_cycle));
  }
  // d(i) linear in i: the maximum is at an end. Reduce the fraction.
  std::int64_t num = narrow(std::max(e.first, e.last), "lifetime");
  std::int64_t den = narrow(e.den, "lifetime denominator");
  const std::int64_t common = std::gcd(num, den);
  return Cycles{num / common, den / common};
}

SbSharingDecision decide_sb_sharing(const PixelStream& p1, const PixelStream& c1,
                                    const PixelStream& c2, const PixelStream& p2, std::int64_t n,
                                    int bytes_per_pixel) {
  if (bytes_per_pixel < 1) {
    throw std::runtime_error(
        fmt::format("SB optimization: bytes_per_pixel: expected >= 1, got {}", bytes_per_pixel));
  }
  const Cycles life1 = max_lifetime(p1, c1, n);
  const Cycles life12 = max_lifetime(p1, c2, n);
  const std::int64_t first_copy = lifetime_pixels(life1, p1);
  const std::int64_t shared = std::max(first_copy, lifetime_pixels(life12, p1));
  // Replicating needs p2(i) > c1(i) for every pixel (p2 - c1 is linear in i: check both ends)
  // and a valid second copy, p2(i) <= c2(i).
  const EndDifferences c1_to_p2 = end_differences(c1, p2, n);  // p2(i) - c1(i)
  const EndDifferences p2_to_c2 = end_differences(p2, c2, n);  // c2(i) - p2(i)
  const bool valid_copy = p2_to_c2.first >= 0 && p2_to_c2.last >= 0;
  const bool reread_after_c1 = valid_copy && c1_to_p2.first > 0 && c1_to_p2.last > 0;
  // (C1 - P1) + (C2 - P2) in pixels; 0 when the re-read would come after its consumer.
  const std::int64_t replicated =
      valid_copy ? first_copy + lifetime_pixels(max_lifetime(p2, c2, n), p2) : 0;
  return decide(shared, replicated, reread_after_c1, n, bytes_per_pixel);
}

}  // namespace edx::arch
