// The frontend memory plan on a small hand-computable frame: SB line FIFOs per pyramid level,
// the DR sharing decision from the DES timing, FIFOs and the scratchpad regions.
#include "arch/frontend/memory_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "sim_core/clock.hpp"
#include "tests/arch/frontend/frontend_test_support.hpp"
#include "tests/arch/memory/memory_test_support.hpp"

namespace edx::arch {
namespace {

using trace::Image;
using trace::Task;

constexpr int kWidth = 100, kHeight = 50;

trace::FrameTrace small_frame(std::int64_t id) {
  trace::FrameTrace f;
  f.frame.frame_id = id;
  const trace::LevelWork level0{0, kWidth, kHeight, kWidth * kHeight, 0, 0};
  const auto row = [&](Task task, Image image) -> trace::TaskRecord& {
    trace::TaskRecord t;
    t.task = task;
    t.image = image;
    f.tasks.push_back(t);
    return f.tasks.back();
  };
  for (Image image : {Image::Left, Image::Right}) {
    auto& fd = row(Task::FD, image);
    fd.pixels = kWidth * kHeight;
    fd.per_level = {level0};
    auto& filter = row(Task::IF, image);
    filter.pixels = kWidth * kHeight;
    filter.per_level = {level0};
    filter.window_size = 7;
  }
  auto& dc = row(Task::DC, Image::Left);
  dc.pixels = kWidth * kHeight;
  dc.per_level = {level0};
  dc.points = 40;
  row(Task::LSS, Image::Left).window_size = 4;
  for (Image image : {Image::Left, Image::Right}) {
    auto& fc = row(Task::FC, image);
    fc.descriptors = fc.keypoints = image == Image::Left ? 50 : 70;
    fc.window_size = 31;
  }
  row(Task::MO, Image::Stereo).comparisons = 100;
  auto& dr = row(Task::DR, Image::Stereo);
  dr.keypoints = dr.windows = 30;
  dr.window_size = 11;
  dr.search_range = 11;
  return f;
}

FrontendConfig config() {
  FrontendConfig c;
  c.clock_mhz = 100;
  c.fe_pixels_per_cycle = 1;
  testing::set_unit(c, Task::DR, "{pixels_per_cycle: 1}");
  return c;
}

TEST(FrontendMemoryPlan, SizesEveryStructureFromTheTraceAndTheTiming) {
  const std::vector<trace::FrameTrace> frames = {small_frame(0), small_frame(1)};
  const FrontendConfig c = config();
  const FrontendSimResult timing = simulate_frontend(frames, kWidth * kHeight, c);
  const FrontendMemoryPlan plan =
      plan_frontend_memory(frames, timing, kWidth, kHeight, c, Device::xc7v690t(), bram());

  // Line FIFOs: fe.L0 7 lines, fc.L0 31, dc.L0 5 (pyrDown), dr.left 11, dr.right 11; 100 px each.
  ASSERT_EQ(plan.stencil_buffers.size(), 5u);
  EXPECT_EQ(plan.stencil_buffers[0].spec.name, "fe.L0");
  EXPECT_EQ(plan.stencil_buffers[0].lines, 7);
  EXPECT_EQ(plan.stencil_buffers[1].lines, 31);
  EXPECT_EQ(plan.stencil_buffers[2].lines, 5);
  EXPECT_EQ(plan.stencil_buffers[3].spec.name, "dr.left");
  EXPECT_EQ(plan.stencil_buffers[4].shift_register_pixels[0], 11 * 21);  // window + search
  EXPECT_EQ(plan.sb_bytes, (7 + 31 + 5 + 11 + 11) * kWidth);

  // DR's pixels: read for FD/IF at FD's start, used by DR at its start + 5 lines + 5 pixels
  // later; both streams at 1 pixel a cycle, so every pixel lives the same number of cycles.
  const sim::ClockDomain clock("frontend", c.clock_mhz);
  std::int64_t longest_left = 0;
  for (const FrontendFrameTiming& t : timing.frames) {
    std::int64_t fd = 0, dr = 0;
    for (const TaskSpan& s : t.tasks) {
      if (s.task == Task::FD && s.image == Image::Left) fd = clock.cycles_in(s.start);
      if (s.task == Task::DR) dr = clock.cycles_in(s.start);
    }
    longest_left = std::max(longest_left, dr + 5 * kWidth + 5 - fd);
  }
  EXPECT_EQ(plan.dr_left.shared_pixels, longest_left);
  EXPECT_TRUE(plan.dr_left.replicate);
  EXPECT_TRUE(plan.dr_right.replicate);
  // The input is double-buffered on chip (the default): DR re-reads the on-chip frame, DRAM is
  // read once a frame (left and right).
  const std::int64_t image = kWidth * kHeight;
  EXPECT_EQ(plan.input_buffer_bytes, 2 * 2 * image);
  EXPECT_EQ(plan.extra_dram_bytes_per_frame, 0);
  EXPECT_EQ(plan.dram_bytes_per_frame, 2 * image);
  // Without the optimization: the paper's rule (lifetime x rate) and the FIFO bound (at most
  // the two frames in flight of each image).
  EXPECT_EQ(plan.sb_bytes_without_optimization,
            (7 + 31 + 5) * kWidth + plan.dr_left.shared_pixels + plan.dr_right.shared_pixels);
  EXPECT_EQ(plan.sb_bytes_without_optimization_bound,
            (7 + 31 + 5) * kWidth + std::min(plan.dr_left.shared_pixels, 2 * image) +
                std::min(plan.dr_right.shared_pixels, 2 * image));

  // FIFOs: FD->FC the larger image's 70 keypoints x 8 B; MO->DR 30 x 8 B; tracks 40 x 12 B.
  ASSERT_EQ(plan.fifos.size(), 3u);
  EXPECT_EQ(plan.fifos[0].bytes, 70 * 8);
  EXPECT_EQ(plan.fifos[1].bytes, 30 * 8);
  EXPECT_EQ(plan.fifos[2].bytes, 40 * 12);
  // SPM: the input frames (two frames, left and right); the two one-level LK pyramids are
  // their left images; previous features, keypoints and descriptors of both images.
  const std::int64_t lists = 40 * 8 + (50 + 70) * 8 + (50 + 70) * 32;
  EXPECT_EQ(plan.spm_bytes, 4 * image + lists);
  EXPECT_TRUE(plan.bram.fits);
  EXPECT_GT(plan.bram.total_blocks, 0.0);

  // DR's re-read from DRAM (the paper's Sec. V-C wording): the two images once more.
  FrontendConfig from_dram = c;
  from_dram.dr_reread = "dram";
  const FrontendMemoryPlan reread =
      plan_frontend_memory(frames, timing, kWidth, kHeight, from_dram, Device::xc7v690t(), bram());
  EXPECT_EQ(reread.extra_dram_bytes_per_frame, 2 * image);
  EXPECT_EQ(reread.spm_bytes, plan.spm_bytes);

  // Input in DRAM: no input buffer, two full LK pyramids in the SPM; DR re-reads both images
  // and DC streams the left one from DRAM.
  FrontendConfig in_dram = c;
  in_dram.input_buffering = "dram";
  const FrontendMemoryPlan dram =
      plan_frontend_memory(frames, timing, kWidth, kHeight, in_dram, Device::xc7v690t(), bram());
  EXPECT_EQ(dram.input_buffer_bytes, 0);
  EXPECT_EQ(dram.spm_bytes, 2 * image + lists);
  EXPECT_EQ(dram.extra_dram_bytes_per_frame, 2 * image + image);
  EXPECT_EQ(dram.dram_bytes_per_frame, 5 * image);
  EXPECT_EQ(dram.sb_bytes, plan.sb_bytes);
}

TEST(FrontendMemoryPlan, InputOptionsAreValidated) {
  FrontendConfig c;
  c.input_buffering = "sram";
  EXPECT_THROW(c.validate(), std::runtime_error);
  c.input_buffering = "dram";
  c.dr_reread = "cache";
  try {
    c.validate();
    FAIL() << "accepted dr_reread: cache";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "frontend.dr_reread: expected on_chip_frame or dram, got 'cache'");
  }
}

TEST(FrontendMemoryPlan, WithoutTheOptimizationDrSharesTheFeatureExtractionBuffer) {
  const std::vector<trace::FrameTrace> frames = {small_frame(0)};
  FrontendConfig c = config();
  c.sb_optimization = false;
  const FrontendSimResult timing = simulate_frontend(frames, kWidth * kHeight, c);
  const FrontendMemoryPlan plan =
      plan_frontend_memory(frames, timing, kWidth, kHeight, c, Device::xc7v690t(), bram());
  EXPECT_EQ(plan.stencil_buffers.size(), 3u);  // no DR buffers of its own
  EXPECT_EQ(plan.sb_bytes, plan.sb_bytes_without_optimization);
  EXPECT_EQ(plan.extra_dram_bytes_per_frame, 0);  // DR reads FD/IF's SB: nothing re-read
}

TEST(FrontendMemoryPlan, AStructureTooBigForTheDeviceIsReported) {
  // Two million descriptors a frame (64 MB of scratchpad) on the ZU9's 912 blocks.
  std::vector<trace::FrameTrace> frames = {small_frame(0)};
  for (auto& t : frames[0].tasks) {
    if (t.task == Task::FC) t.descriptors = 2'000'000;
  }
  const FrontendConfig c = config();
  const FrontendSimResult timing = simulate_frontend(frames, kWidth * kHeight, c);
  const FrontendMemoryPlan plan =
      plan_frontend_memory(frames, timing, kWidth, kHeight, c, Device::zu9eg(), bram());
  EXPECT_FALSE(plan.bram.fits);
  EXPECT_NE(plan.bram.message.find("ZU9EG has 912"), std::string::npos) << plan.bram.message;
}

}  // namespace
}  // namespace edx::arch
