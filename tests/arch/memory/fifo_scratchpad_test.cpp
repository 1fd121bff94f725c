// FIFO and scratchpad sizing and their structures' BRAM mapping (the memory kind `bram`).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "arch/memory/fifo.hpp"
#include "arch/memory/scratchpad.hpp"
#include "tests/arch/memory/memory_test_support.hpp"

namespace edx::arch {
namespace {

TEST(FifoSizing, BytesAndBram) {
  // 256 keypoints of 4 bytes: 32 bits x 256 words fit one 512 x 36 BRAM18 half.
  const FifoSizing small = size_fifo({"keypoints", 256, 4});
  EXPECT_EQ(small.bytes, 1024);
  EXPECT_EQ(small.structure.width_bits, 32);
  EXPECT_EQ(small.structure.depth_words, 256);
  EXPECT_DOUBLE_EQ(bram().mapping(small.structure).blocks, 0.5);
  // 5000 entries of 8 bytes: 64 x 5000 -> 10 blocks (512 x 72: 1 x 10; 1K x 36: 2 x 5).
  const FifoSizing big = size_fifo({"points", 5000, 8});
  EXPECT_EQ(big.bytes, 40000);
  EXPECT_DOUBLE_EQ(bram().mapping(big.structure).blocks, 10.0);
}

TEST(FifoSizing, RejectsEmptyFifos) {
  try {
    size_fifo({"keypoints", 0, 4});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("keypoints"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("entries"), std::string::npos);
  }
  EXPECT_THROW(size_fifo({"keypoints", 4, 0}), std::runtime_error);
}

TEST(ScratchpadSizing, RegionsRoundUpToWords) {
  ScratchpadSpec spec;
  spec.name = "backend_spm";
  spec.word_bits = 64;
  spec.regions = {{"H", 100}, {"P", 64}, {"R", 1}};
  const ScratchpadSizing s = size_scratchpad(spec);
  EXPECT_EQ(s.bytes, 165);
  EXPECT_EQ(s.words, (std::vector<std::int64_t>{13, 8, 1}));  // ceil(800/64), 512/64, ceil(8/64)
  EXPECT_EQ(s.depth_words, 22);
  EXPECT_EQ(s.structure.width_bits, 64);
  EXPECT_DOUBLE_EQ(bram().mapping(s.structure).blocks, 1.0);  // one 512 x 72

  // A 30-pose MSCKF covariance (n = 15 + 6 x 30 = 195 doubles square): 195^2 x 8 = 304200 B
  // -> 38025 words of 64 bits -> 512 x 72: 75 rows; 1K x 36: 2 x 38 = 76 -> 75 blocks.
  ScratchpadSpec cov;
  cov.regions = {{"P", 195 * 195 * 8}};
  const ScratchpadSizing c = size_scratchpad(cov);
  EXPECT_EQ(c.depth_words, 38025);
  EXPECT_DOUBLE_EQ(bram().mapping(c.structure).blocks, 75.0);
}

TEST(ScratchpadSizing, RejectsNegativeRegions) {
  ScratchpadSpec spec;
  spec.regions = {{"H", -1}};
  try {
    size_scratchpad(spec);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'H'"), std::string::npos);
  }
  spec.regions = {{"H", 8}};
  spec.word_bits = 0;
  EXPECT_THROW(size_scratchpad(spec), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
