#include "workloads/backend/registration/bow/descriptor.hpp"

#include <stdexcept>

namespace edx::bow {

void BitCounter::add(const PackedDescriptor& d) {
  for (int w = 0; w < 4; ++w) {
    // Visit only the set bits: about half of 64 per word.
    for (std::uint64_t bits = d[w]; bits != 0; bits &= bits - 1) {
      ++counts_[64 * w + std::countr_zero(bits)];
    }
  }
  ++n_;
}

PackedDescriptor BitCounter::majority() const {
  if (n_ == 0) throw std::logic_error("BitCounter::majority: no descriptors added");
  PackedDescriptor out{};
  for (int b = 0; b < 256; ++b) {
    if (2 * static_cast<std::size_t>(counts_[b]) >= n_) out[b / 64] |= std::uint64_t{1} << (b % 64);
  }
  return out;
}

Descriptor majority_centroid(std::span<const Descriptor> descriptors) {
  if (descriptors.empty()) throw std::runtime_error("majority_centroid: empty descriptor set");
  BitCounter counter;
  for (const Descriptor& d : descriptors) counter.add(pack(d));
  return unpack(counter.majority());
}

}  // namespace edx::bow
