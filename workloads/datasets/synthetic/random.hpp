#pragma once
// Seed derivation for the synthetic world: every random stream (textures, layout, routes, noise)
// gets its own seed derived from the user's seed and a purpose tag, so that streams never depend
// on the order in which others were consumed.
#include <cmath>
#include <cstdint>
#include <random>
#include <string_view>

namespace edx::synthetic {

/// SplitMix64 finaliser (Steele et al. 2014): a bijective 64-bit mixing function.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// FNV-1a hash of a tag, used to name random streams.
constexpr std::uint64_t hash_tag(std::string_view tag) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (const char c : tag) {
    h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  }
  return h;
}

/// Seed of the stream `tag`/`index` under the user's `seed`.
constexpr std::uint64_t derive_seed(std::uint64_t seed, std::string_view tag,
                                    std::uint64_t index = 0) {
  return mix64(mix64(seed ^ hash_tag(tag)) + index);
}

using Rng = std::mt19937_64;

/// Uniform real in [lo, hi) from a 53-bit draw; unlike std::uniform_real_distribution its
/// result is specified exactly, so output files do not depend on the standard library.
inline double uniform(Rng& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform integer in [lo, hi] (inclusive), exactly specified (modulo bias < 2^-40 for the
/// small ranges used here).
inline int uniform_int(Rng& rng, int lo, int hi) {
  return lo + static_cast<int>(rng() % static_cast<std::uint64_t>(hi - lo + 1));
}

/// Standard normal draw by Box–Muller from two exactly specified uniforms.
inline double normal(Rng& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

}  // namespace edx::synthetic
