// BRAM36 mapping (UG473 / UG573 aspect ratios), device totals (DS180, DS891) and the budget check.
#include "arch/memory/bram.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "tests/arch/memory/memory_test_support.hpp"

namespace edx::arch {
namespace {

TEST(BramMapping, EightBitLineOf640PixelsTakesOneBram18) {
  // 36Kb aspects give ceil(8/9)*ceil(640/4096) = 1 block; BRAM18 2K x 9 gives 1 half.
  const BramMapping m = map_to_bram(8, 640);
  EXPECT_DOUBLE_EQ(m.blocks, 0.5);
  EXPECT_TRUE(m.aspect.half);
  EXPECT_EQ(m.aspect.width_bits, 9);
  EXPECT_EQ(m.aspect.depth_words, 2048);
  EXPECT_DOUBLE_EQ(map_to_bram(8, 640, /*allow_bram18=*/false).blocks, 1.0);
}

TEST(BramMapping, Wide512WordMemoryUsesSimpleDualPort72) {
  const BramMapping m = map_to_bram(72, 512);
  EXPECT_DOUBLE_EQ(m.blocks, 1.0);
  EXPECT_FALSE(m.aspect.half);  // tie with two 512 x 36 halves goes to the BRAM36
  EXPECT_EQ(m.aspect.width_bits, 72);
  EXPECT_TRUE(m.aspect.simple_dual_port_only);
}

TEST(BramMapping, PicksFewestBlocksAcrossAspects) {
  // 64 x 1000: 72x512 -> 1*2 = 2, 36x1K -> 2*1 = 2, 18x2K -> 4*1 = 4, 9x4K -> 8, 1x32K -> 64.
  const BramMapping m = map_to_bram(64, 1000);
  EXPECT_DOUBLE_EQ(m.blocks, 2.0);
  EXPECT_EQ(m.columns * m.rows, 2);
  // 1 x 40000: 32K x 1 needs 2 blocks; three 16K x 1 BRAM18 halves are 1.5.
  EXPECT_DOUBLE_EQ(map_to_bram(1, 40000).blocks, 1.5);
  EXPECT_DOUBLE_EQ(map_to_bram(1, 40000, false).blocks, 2.0);
  // 32 x 1024 fills a 1K x 36 exactly; 32 x 512 fits one 512 x 36 half.
  EXPECT_DOUBLE_EQ(map_to_bram(32, 1024).blocks, 1.0);
  EXPECT_DOUBLE_EQ(map_to_bram(32, 512).blocks, 0.5);
  // 144 bits x 4096 words: 2 x 8 blocks of 512 x 72 = 16 = 4 x 4 of 1K x 36.
  EXPECT_DOUBLE_EQ(map_to_bram(144, 4096).blocks, 16.0);
}

TEST(BramMapping, EmptyAndNegativeSizes) {
  EXPECT_DOUBLE_EQ(map_to_bram(0, 100).blocks, 0.0);
  EXPECT_DOUBLE_EQ(map_to_bram(8, 0).blocks, 0.0);
  EXPECT_THROW(map_to_bram(-1, 10), std::runtime_error);
  EXPECT_THROW(map_to_bram(8, -10), std::runtime_error);
}

TEST(BramBytes, ParityAndDataConventions) {
  EXPECT_DOUBLE_EQ(bytes_of_blocks(1, true), 4608.0);   // 36 Kb / 8
  EXPECT_DOUBLE_EQ(bytes_of_blocks(1, false), 4096.0);  // 32 Kb / 8
  EXPECT_DOUBLE_EQ(to_mib(bytes_of_blocks(256, false)), 1.0);
}

TEST(BramDevice, DatasheetTotalsReproduceThePaperUtilizations) {
  const Device v7 = Device::xc7v690t();
  EXPECT_EQ(v7.bram36_blocks, 1470);
  // The paper's resource table (Sec. VII-B): 350671 LUT = 80.9 %, 239347 FF = 27.6 %,
  // 1284 DSP = 35.6 % of the Virtex-7.
  EXPECT_NEAR(350671.0 / static_cast<double>(v7.luts), 0.809, 0.0006);
  EXPECT_NEAR(239347.0 / static_cast<double>(v7.flip_flops), 0.276, 0.0006);
  EXPECT_NEAR(1284.0 / static_cast<double>(v7.dsps), 0.356, 0.0011);
  // 5.0 MB BRAM = 87.5 %: matches the data-bit capacity in MiB (1470 x 4096 B = 5.74 MiB) to
  // within 0.5 points, not the capacity with parity (6.46 MiB, 77 %).
  const double data_mib = to_mib(bytes_of_blocks(static_cast<double>(v7.bram36_blocks), false));
  const double parity_mib = to_mib(bytes_of_blocks(static_cast<double>(v7.bram36_blocks), true));
  EXPECT_NEAR(5.0 / data_mib, 0.875, 0.005);
  EXPECT_GT(std::abs(5.0 / parity_mib - 0.875), 0.05);

  const Device zu9 = Device::zu9eg();
  EXPECT_EQ(zu9.bram36_blocks, 912);
  EXPECT_EQ(zu9.luts, 274080);
  EXPECT_EQ(zu9.flip_flops, 548160);
  EXPECT_EQ(zu9.dsps, 2520);
  // DS891: 32.1 Mb of block RAM = 912 x 36 Kb.
  EXPECT_NEAR(912.0 * 36.0 / 1024.0, 32.1, 0.05);
}

TEST(BramDevice, ByName) {
  EXPECT_EQ(Device::by_name("XC7V690T").bram36_blocks, 1470);
  EXPECT_EQ(Device::by_name("zu9cg").name, "ZU9CG");
  EXPECT_EQ(Device::by_name("zu9cg").bram36_blocks, 912);
  try {
    Device::by_name("xcku115");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("xcku115"), std::string::npos);
  }
}

TEST(BramBudget, TotalsStructuresAndChecksTheDevice) {
  const std::vector<MemoryStructure> structures = {
      {"line_fifo", 8, 640, 4},       // 4 x 0.5
      {"descriptors", 256, 1000, 1},  // 512x72: 4 x 2 = 8; 1K x 36: 8; BRAM18 1K x 18: 15 x 0.5
  };
  const BramBudget fits = check_bram("frontend", structures, Device::zu9eg(), bram());
  EXPECT_DOUBLE_EQ(fits.structures[0].blocks, 2.0);
  EXPECT_DOUBLE_EQ(fits.structures[1].blocks, 7.5);
  EXPECT_DOUBLE_EQ(fits.total_blocks, 9.5);
  EXPECT_TRUE(fits.fits);
  EXPECT_DOUBLE_EQ(fits.utilization, 9.5 / 912.0);
  EXPECT_DOUBLE_EQ(fits.total_bytes(true), 9.5 * 4608.0);

  const std::vector<MemoryStructure> big = {{"frame_buffer", 8, 1280 * 720, 8}};
  // 8 x 921600: 9-bit 4K aspect -> 225 blocks; BRAM18 2K x 9 -> 450 halves = 225; x 8 = 1800.
  const BramBudget overflow = check_bram("double-buffered images", big, Device::xc7v690t(), bram());
  EXPECT_DOUBLE_EQ(overflow.total_blocks, 1800.0);
  EXPECT_FALSE(overflow.fits);
  EXPECT_NE(overflow.message.find("double-buffered images"), std::string::npos);
  EXPECT_NE(overflow.message.find("XC7V690T"), std::string::npos);
  EXPECT_EQ(overflow.to_json()["fits"], false);
}

TEST(BramBudget, RejectsBadStructures) {
  EXPECT_THROW(check_bram("x", {{"neg", 8, 10, -1}}, Device::zu9eg(), bram()), std::runtime_error);
  EXPECT_THROW(check_bram("x", {{"", 8, 10, 1}}, Device::zu9eg(), bram()), std::runtime_error);
}

}  // namespace
}  // namespace edx::arch
