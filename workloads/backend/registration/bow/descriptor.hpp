#pragma once
// 256-bit ORB (rBRIEF) descriptors as the bag-of-words code sees them: the frontend's 32 bytes
// (frontend::Feature::descriptor) and a packed form of four 64-bit words for fast Hamming
// distances, d(a, b) = popcount(a XOR b) summed over the four words.
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>

namespace edx::bow {

/// An ORB descriptor exactly as the frontend stores it (frontend::Feature::descriptor).
using Descriptor = std::array<std::uint8_t, 32>;
/// The same 256 bits as four 64-bit words (host byte order).
using PackedDescriptor = std::array<std::uint64_t, 4>;

static_assert(std::endian::native == std::endian::little,
              "bit numbering of the packed form assumes a little-endian host");

inline PackedDescriptor pack(const Descriptor& d) {
  PackedDescriptor p;
  std::memcpy(p.data(), d.data(), sizeof p);
  return p;
}

inline Descriptor unpack(const PackedDescriptor& p) {
  Descriptor d;
  std::memcpy(d.data(), p.data(), sizeof d);
  return d;
}

/// Number of differing bits, 0..256.
inline int hamming_distance(const PackedDescriptor& a, const PackedDescriptor& b) {
  return std::popcount(a[0] ^ b[0]) + std::popcount(a[1] ^ b[1]) + std::popcount(a[2] ^ b[2]) +
         std::popcount(a[3] ^ b[3]);
}

inline int hamming_distance(const Descriptor& a, const Descriptor& b) {
  return hamming_distance(pack(a), pack(b));
}

/// Per-bit counts of set bits over a set of descriptors, for majority centroids.
class BitCounter {
 public:
  void add(const PackedDescriptor& d);
  /// Bitwise majority of the n descriptors added: bit b is set iff 2 * count_b >= n, so ties
  /// (even n) give 1, as DBoW2's FORB::meanValue. Throws std::logic_error when n = 0.
  PackedDescriptor majority() const;
  std::size_t size() const { return n_; }

 private:
  std::array<std::uint32_t, 256> counts_{};
  std::size_t n_ = 0;
};

/// The k-majority centroid of `descriptors` (bitwise majority, see BitCounter::majority): the
/// descriptor minimising the summed Hamming distance to them. Throws on an empty set.
Descriptor majority_centroid(std::span<const Descriptor> descriptors);

}  // namespace edx::bow
