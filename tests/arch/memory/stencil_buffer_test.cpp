// Stencil buffer sizing (paper Sec. V-C, Fig. 11) and the SB optimization rule (Fig. 12).
#include "arch/memory/stencil_buffer.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "tests/arch/memory/memory_test_support.hpp"

namespace edx::arch {
namespace {

StencilBufferSpec paper_example(std::int64_t width = 640) {
  StencilBufferSpec spec;
  spec.name = "fd_if";
  spec.line_width_pixels = width;
  spec.bytes_per_pixel = 1;
  spec.consumers = {{"4x3", 4, 3}, {"3x3", 3, 3}};
  return spec;
}

TEST(StencilBuffer, PaperExampleOfFig11) {
  const StencilBuffer sb = size_stencil_buffer(paper_example());
  EXPECT_EQ(sb.lines, 4);  // 4 cascaded FIFOs
  EXPECT_EQ(sb.fifo_depth_pixels, 640);
  EXPECT_EQ(sb.fifo_bytes, 4 * 640);
  EXPECT_EQ(sb.shift_register_pixels, (std::vector<std::int64_t>{12, 9}));
  EXPECT_EQ(sb.shift_register_bytes, 21);
  // The first three FIFOs write to both shift registers, the last only to the first.
  const std::vector<std::vector<int>> feeds = {{0, 1}, {0, 1}, {0, 1}, {0}};
  EXPECT_EQ(sb.feeds, feeds);
  const std::vector<MemoryStructure> structures = sb.memory_structures();
  ASSERT_EQ(structures.size(), 1u);
  EXPECT_EQ(structures[0].width_bits, 8);
  EXPECT_EQ(structures[0].depth_words, 640);
  EXPECT_EQ(structures[0].count, 4);
  // Each FIFO: 8 bits x 640 words -> one 2K x 9 BRAM18 half.
  EXPECT_DOUBLE_EQ(bram().mapping(structures[0]).blocks, 0.5);
  EXPECT_DOUBLE_EQ(bram().cost(structures[0]).bram, 2.0);
  EXPECT_DOUBLE_EQ(check_bram("sb", structures, Device::zu9eg(), bram()).total_blocks, 2.0);
}

TEST(StencilBuffer, WideLinesAndTwoBytePixels) {
  StencilBufferSpec spec = paper_example(1280);
  spec.bytes_per_pixel = 2;
  spec.consumers = {{"gauss", 7, 7}};
  const StencilBuffer sb = size_stencil_buffer(spec);
  EXPECT_EQ(sb.lines, 7);
  EXPECT_EQ(sb.fifo_bytes, 7 * 1280 * 2);
  EXPECT_EQ(sb.shift_register_pixels, (std::vector<std::int64_t>{49}));
  EXPECT_EQ(sb.shift_register_bytes, 98);
  // 16 bits x 1280 words: one 2K x 18 BRAM36 per FIFO (BRAM18 halves also make 1.0).
  EXPECT_DOUBLE_EQ(bram().mapping(sb.memory_structures()[0]).blocks, 1.0);
  EXPECT_DOUBLE_EQ(bram().cost(sb.memory_structures()[0]).bram, 7.0);
  EXPECT_EQ(sb.feeds.size(), 7u);
  EXPECT_EQ(sb.feeds[6], (std::vector<int>{0}));
}

TEST(StencilBuffer, RejectsBadSpecsNamingTheField) {
  StencilBufferSpec none = paper_example();
  none.consumers.clear();
  EXPECT_THROW(size_stencil_buffer(none), std::runtime_error);
  StencilBufferSpec flat = paper_example();
  flat.consumers[1].height = 0;
  try {
    size_stencil_buffer(flat);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("height"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("fd_if"), std::string::npos);
  }
  StencilBufferSpec narrow = paper_example(2);
  EXPECT_THROW(size_stencil_buffer(narrow), std::runtime_error);  // 3-wide window, 2-pixel line
}

TEST(SbSharing, ReplicatesWhenTheRereadComesAfterTheFirstConsumer) {
  // P1 = 0, C1 = 10, C2 = 1000, P2 = 900: one SB holds 1000 pixels; two hold 10 + 100.
  const SbSharingDecision d = decide_sb_sharing({0, 10, 1000, 900, 640 * 480, 1});
  EXPECT_EQ(d.shared_pixels, 1000);
  EXPECT_EQ(d.replicated_pixels, 110);
  EXPECT_TRUE(d.replicate);
  EXPECT_EQ(d.saved_pixels, 890);
  EXPECT_EQ(d.extra_dram_bytes_per_frame, 307200);
}

TEST(SbSharing, SharesWhenTheRereadWouldComeTooEarly) {
  // P2 = 5 < C1 = 10: replicated (10 + 995) exceeds shared (1000).
  const SbSharingDecision early = decide_sb_sharing({0, 10, 1000, 5, 100, 2});
  EXPECT_EQ(early.shared_pixels, 1000);
  EXPECT_EQ(early.replicated_pixels, 1005);
  EXPECT_FALSE(early.replicate);
  EXPECT_EQ(early.saved_pixels, 0);
  EXPECT_EQ(early.extra_dram_bytes_per_frame, 0);
  // P2 = C1 is not "P2 > C1": both layouts need 1000 pixels, keep one SB and one DRAM read.
  const SbSharingDecision tie = decide_sb_sharing({0, 10, 1000, 10, 100, 1});
  EXPECT_EQ(tie.replicated_pixels, 1000);
  EXPECT_FALSE(tie.replicate);
}

TEST(SbSharing, RejectsInconsistentCycles) {
  EXPECT_THROW(decide_sb_sharing({0, 20, 10, 15, 1, 1}), std::runtime_error);   // C2 < C1
  EXPECT_THROW(decide_sb_sharing({30, 20, 40, 35, 1, 1}), std::runtime_error);  // C1 < P1
  EXPECT_THROW(decide_sb_sharing({0, 20, 40, 45, 1, 1}), std::runtime_error);   // P2 > C2
}

TEST(SbStreams, LifetimeIsExactAtTheEnds) {
  // Same rate: every pixel lives 10 cycles.
  const Cycles same = max_lifetime({0, 1, 1}, {10, 1, 1}, 1000);
  EXPECT_EQ(same.numerator, 10);
  EXPECT_EQ(same.denominator, 1);
  // Producer 2 px/cycle, consumer 1 px/cycle from cycle 5, 100 pixels:
  // d(i) = 5 + i (1 - 1/2), d(99) = 54.5 cycles.
  const Cycles slow = max_lifetime({0, 2, 1}, {5, 1, 1}, 100);
  EXPECT_EQ(slow.numerator, 109);
  EXPECT_EQ(slow.denominator, 2);
  EXPECT_EQ(slow.ceil(), 55);
  // Consumer 2 px/cycle from cycle 60 on a 1 px/cycle producer: d(i) = 60 - i/2, max d(0) = 60.
  const Cycles fast = max_lifetime({0, 1, 1}, {60, 2, 1}, 100);
  EXPECT_EQ(fast.numerator, 60);
  EXPECT_EQ(fast.denominator, 1);
  // From cycle 40 the consumer would overtake: d(99) = 40 - 49.5 < 0.
  EXPECT_THROW(max_lifetime({0, 1, 1}, {40, 2, 1}, 100), std::runtime_error);
  // Two pixels every three cycles (rate 2/3) against one a cycle from cycle 7, 10 pixels:
  // d(i) = 7 + i (1 - 3/2) = 7 - i/2, max d(0) = 7; reversed roles d(i) = 7 + i/2 -> 11.5.
  EXPECT_EQ(max_lifetime({0, 2, 3}, {7, 1, 1}, 10).numerator, 7);
  const Cycles reversed = max_lifetime({0, 1, 1}, {7, 2, 3}, 10);
  EXPECT_EQ(reversed.numerator, 23);
  EXPECT_EQ(reversed.denominator, 2);
  EXPECT_THROW(max_lifetime({0, 0, 1}, {7, 1, 1}, 10), std::runtime_error);
}

TEST(SbStreams, UnitRateStreamsReproduceTheScalarRule) {
  const SbSharingDecision d =
      decide_sb_sharing(PixelStream{0, 1, 1}, PixelStream{10, 1, 1}, PixelStream{1000, 1, 1},
                        PixelStream{900, 1, 1}, 640, 1);
  EXPECT_EQ(d.shared_pixels, 1000);
  EXPECT_EQ(d.replicated_pixels, 110);
  EXPECT_TRUE(d.replicate);
  EXPECT_EQ(d.extra_dram_bytes_per_frame, 640);
}

TEST(SbStreams, TwoPixelsPerCycleDoublesThePixelSizes) {
  // Lifetimes 10, 1000 and 100 cycles at 2 px/cycle: 20, 2000 and 200 pixels.
  const SbSharingDecision d =
      decide_sb_sharing(PixelStream{0, 2, 1}, PixelStream{10, 2, 1}, PixelStream{1000, 2, 1},
                        PixelStream{900, 2, 1}, 1000, 2);
  EXPECT_EQ(d.shared_pixels, 2000);
  EXPECT_EQ(d.replicated_pixels, 220);
  EXPECT_TRUE(d.replicate);
  EXPECT_EQ(d.extra_dram_bytes_per_frame, 2000);
  // A re-read from cycle 5 starts before C1 consumes pixel 0 (cycle 10): no replication.
  const SbSharingDecision early =
      decide_sb_sharing(PixelStream{0, 2, 1}, PixelStream{10, 2, 1}, PixelStream{2000, 1, 1},
                        PixelStream{5, 1, 1}, 1000, 1);
  EXPECT_FALSE(early.replicate);
  EXPECT_EQ(early.extra_dram_bytes_per_frame, 0);
}

}  // namespace
}  // namespace edx::arch
