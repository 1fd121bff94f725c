// Task cycle formulas against hand-computed values (docs/MODEL.md, frontend tasks).
#include "arch/frontend/task_timing.hpp"

#include <gtest/gtest.h>

#include "tests/arch/frontend/frontend_test_support.hpp"

namespace edx::arch {
namespace {

trace::TaskRecord pyramid_task(trace::Task task, std::int64_t window) {
  trace::TaskRecord t;
  t.task = task;
  t.window_size = window;
  t.per_level = {{0, 100, 50, 5000, 0, 0}, {1, 50, 25, 1250, 0, 0}};
  t.pixels = 6250;
  t.levels = 2;
  return t;
}

TEST(TaskTiming, StencilStreamsPayTheirHaloOncePerLevel) {
  FrontendConfig c;
  c.fe_pixels_per_cycle = 2;
  c.fd_stencil = 7;
  // halo: 3 lines + 3 pixels per level: (3*100 + 3) + (3*50 + 3) = 456.
  EXPECT_EQ(stencil_halo_pixels(pyramid_task(trace::Task::FD, 0), 7), 456);
  // ceil((6250 + 456) / 2) = 3353.
  EXPECT_EQ(task_cycles(pyramid_task(trace::Task::FD, 0), 0, c), 3353);
  // IF uses the trace's kernel side (5): halo (2*100+2) + (2*50+2) = 304; ceil(6554/2) = 3277.
  EXPECT_EQ(task_cycles(pyramid_task(trace::Task::IF, 5), 0, c), 3277);
  // DC: 3x3 Scharr at 1.5 px/cycle: halo 101 + 51 = 152; ceil(6402 / 1.5) = 4268.
  testing::set_unit(c, trace::Task::DC, "{pixels_per_cycle: 1.5}");
  EXPECT_EQ(task_cycles(pyramid_task(trace::Task::DC, 3), 0, c), 4268);
}

TEST(TaskTiming, DescriptorsComparisonsWindowsAndSolves) {
  FrontendConfig c;
  trace::TaskRecord fc;
  fc.task = trace::Task::FC;
  fc.descriptors = 10;
  fc.window_size = 31;
  testing::set_unit(c, trace::Task::FC, "{patch_rows_per_cycle: 1, tests_per_cycle: 32}");
  EXPECT_EQ(task_cycles(fc, 0, c), 10 * (31 + 8));
  // ceil(31/4) = 8
  testing::set_unit(c, trace::Task::FC, "{patch_rows_per_cycle: 4, tests_per_cycle: 256}");
  EXPECT_EQ(task_cycles(fc, 0, c), 10 * (8 + 1));

  trace::TaskRecord mo;
  mo.task = trace::Task::MO;
  mo.comparisons = 1001;
  testing::set_unit(c, trace::Task::MO, "{comparators: 4}");
  EXPECT_EQ(task_cycles(mo, 0, c), 251);

  trace::TaskRecord dr;
  dr.task = trace::Task::DR;
  dr.keypoints = dr.windows = 100;
  dr.window_size = 11;
  dr.search_range = 11;
  testing::set_unit(c, trace::Task::DR, "{pixels_per_cycle: 0.25, sad_units: 11}");
  EXPECT_EQ(task_cycles(dr, 10000, c), 40000);  // the image stream dominates
  // 100 windows x ceil(11/4) x 11 rows = 3300
  testing::set_unit(c, trace::Task::DR, "{pixels_per_cycle: 100, sad_units: 4}");
  EXPECT_EQ(task_cycles(dr, 10000, c), 3300);
  trace::TaskRecord no_matches = dr;
  no_matches.keypoints = no_matches.windows = 0;
  EXPECT_EQ(task_cycles(no_matches, 10000, c), 0);

  trace::TaskRecord lss;
  lss.task = trace::Task::LSS;
  lss.window_size = 16;
  lss.points = 20;
  lss.iterations = 100;
  testing::set_unit(c, trace::Task::LSS, "{macs_per_cycle: 64}");
  EXPECT_EQ(task_cycles(lss, 0, c), 256 * (9 * 100 + 3 * 20) / 64);
}

}  // namespace
}  // namespace edx::arch
