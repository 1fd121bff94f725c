#pragma once
// A seeded pseudo-random permutation of the indices [0, n), evaluated one index at a time in
// O(1) memory: random sampling draws `samples` distinct grid points as perm(0), perm(1), ...
// without storing the draws or the grid (issue 45: 10^6 samples of a 10^6-point grid took 28 s
// and a set of every draw before the first point).
#include <array>
#include <cstdint>
#include <stdexcept>

namespace edx::arch {

/// splitmix64 (Steele, Lea and Flood 2014): a fixed, portable stream; returns the next value and
/// advances `state`.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// A bijection of [0, n) for 1 <= n <= 2^126: a balanced Feistel network (Luby and Rackoff 1988)
/// on 2h bits, the smallest with 2^(2h) >= n, cycle-walked into [0, n) (Black and Rogaway 2002):
///   round r:  (L, R) -> (R, L xor (F(R xor k_r) mod 2^h)),   F = splitmix64's mixer,
///   perm(i) = the first of E(i), E(E(i)), ... below n.
/// Each round is a bijection of [0, 2^(2h)), so E is; walking E's cycle from i < n until it
/// re-enters [0, n) is then a bijection of [0, n). Since 2^(2h) < 4n, a walk takes fewer than 4
/// steps on average. The keys k_r come from the seed's splitmix64 stream: the same seed gives
/// the same permutation on every machine.
class IndexPermutation {
 public:
  /// Indices of grids beyond 2^64 points (a dozen parameters of 40 values) need 128 bits.
  using Index = unsigned __int128;
  static constexpr Index kMaxSize = Index{1} << 126;

  IndexPermutation(Index n, std::uint64_t seed) : n_(n) {
    if (n_ == 0 || n_ > kMaxSize) throw std::invalid_argument("IndexPermutation: n out of range");
    while ((Index{1} << (2 * half_bits_)) < n_) ++half_bits_;
    mask_ = (std::uint64_t{1} << half_bits_) - 1;  // h <= 63
    for (std::uint64_t& key : keys_) key = splitmix64(seed);
  }
  Index size() const { return n_; }
  /// perm(i), for i < size().
  Index operator()(Index i) const {
    do {
      i = encrypt(i);
    } while (i >= n_);
    return i;
  }

 private:
  Index encrypt(Index x) const {
    std::uint64_t left = static_cast<std::uint64_t>(x >> half_bits_);
    std::uint64_t right = static_cast<std::uint64_t>(x) & mask_;
    for (const std::uint64_t key : keys_) {
      std::uint64_t state = right ^ key;
      const std::uint64_t mixed = left ^ (splitmix64(state) & mask_);
      left = right;
      right = mixed;
    }
    return (Index{left} << half_bits_) | right;
  }

  Index n_;
  unsigned half_bits_ = 1;  ///< h >= 1: a domain of at least 4 (two 1-bit halves)
  std::uint64_t mask_ = 1;
  std::array<std::uint64_t, 6> keys_{};
};

}  // namespace edx::arch
