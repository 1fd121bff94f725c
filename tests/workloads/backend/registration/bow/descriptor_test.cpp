// Hamming distance and bitwise-majority centroids of 256-bit ORB descriptors, by hand.
#include "workloads/backend/registration/bow/descriptor.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace edx::bow {
namespace {

Descriptor with_bytes(std::initializer_list<std::pair<int, std::uint8_t>> bytes) {
  Descriptor d{};
  for (const auto& [index, value] : bytes) d[index] = value;
  return d;
}

TEST(BowDescriptor, HammingDistanceCountsDifferingBits) {
  const Descriptor zero{};
  Descriptor ones;
  ones.fill(0xFF);
  EXPECT_EQ(hamming_distance(zero, zero), 0);
  EXPECT_EQ(hamming_distance(zero, ones), 256);
  // 0x0F vs 0xF0: 8 bits; byte 31 0x01 vs 0x00: 1 bit; byte 8 0x81 vs 0x80: 1 bit.
  EXPECT_EQ(hamming_distance(with_bytes({{0, 0x0F}, {31, 0x01}, {8, 0x81}}),
                             with_bytes({{0, 0xF0}, {8, 0x80}})),
            10);
}

TEST(BowDescriptor, MajorityCentroidOfOddSetTakesBitsSetInMostDescriptors) {
  // byte 0: 0b111, 0b011, 0b001 -> bit 0 in 3/3, bit 1 in 2/3, bit 2 in 1/3 -> 0b011.
  // byte 31: 0x80 in two of three -> 0x80; byte 16: 0x10 in one of three -> 0.
  const std::vector<Descriptor> set = {with_bytes({{0, 0b111}, {31, 0x80}, {16, 0x10}}),
                                       with_bytes({{0, 0b011}, {31, 0x80}}),
                                       with_bytes({{0, 0b001}})};
  EXPECT_EQ(majority_centroid(set), with_bytes({{0, 0b011}, {31, 0x80}}));
}

TEST(BowDescriptor, MajorityCentroidBreaksTiesTowardsOne) {
  // Two descriptors: every bit set in exactly one of them is a tie (1 of 2) -> 1, as DBoW2.
  const std::vector<Descriptor> set = {with_bytes({{0, 0x01}, {20, 0xF0}}),
                                       with_bytes({{0, 0x02}, {20, 0x0F}, {5, 0x00}})};
  EXPECT_EQ(majority_centroid(set), with_bytes({{0, 0x03}, {20, 0xFF}}));
  // Four descriptors, bit 3 of byte 7 in two of them: tie -> 1; bit 4 in one: 0.
  const std::vector<Descriptor> four = {with_bytes({{7, 0x18}}), with_bytes({{7, 0x08}}),
                                        with_bytes({}), with_bytes({})};
  EXPECT_EQ(majority_centroid(four), with_bytes({{7, 0x08}}));
}

TEST(BowDescriptor, MajorityCentroidMinimisesSummedDistance) {
  const std::vector<Descriptor> set = {with_bytes({{0, 0xFF}, {1, 0x0F}}),
                                       with_bytes({{0, 0xFE}, {2, 0x01}}),
                                       with_bytes({{0, 0x7F}, {1, 0x01}})};
  const Descriptor centroid = majority_centroid(set);
  auto cost = [&](const Descriptor& c) {
    int sum = 0;
    for (const Descriptor& d : set) sum += hamming_distance(c, d);
    return sum;
  };
  // Flipping any single bit of the centroid cannot lower the summed distance.
  for (int bit = 0; bit < 256; ++bit) {
    Descriptor flipped = centroid;
    flipped[bit / 8] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    EXPECT_GE(cost(flipped), cost(centroid)) << "bit " << bit;
  }
  EXPECT_EQ(centroid, with_bytes({{0, 0xFF}, {1, 0x01}}));
}

TEST(BowDescriptor, MajorityCentroidOfNothingThrows) {
  EXPECT_THROW(majority_centroid({}), std::runtime_error);
}

}  // namespace
}  // namespace edx::bow
