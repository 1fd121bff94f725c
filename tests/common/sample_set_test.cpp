// Sample statistics against hand-computed values (the definitions at the top of
// common/sample_set.hpp).
#include "common/sample_set.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace edx::common {
namespace {

// Samples 2 4 4 4 5 5 7 9 (n = 8, already sorted):
//   mean = 40 / 8 = 5; squared deviations 9+1+1+1+0+0+4+16 = 32
//   population SD = sqrt(32 / 8) = 2;  sample SD = sqrt(32 / 7) = 2.1380899352993950
//   RSD = 2.1380899352993950 / 5 = 0.42761798705987900
//   p50: h = 7 * 0.50 = 3.5  -> x3 + 0.5 (x4 - x3) = 4 + 0.5 * 1 = 4.5
//   p90: h = 7 * 0.90 = 6.3  -> x6 + 0.3 (x7 - x6) = 7 + 0.3 * 2 = 7.6
//   p99: h = 7 * 0.99 = 6.93 -> 7 + 0.93 * 2 = 8.86
//   p25: h = 1.75 -> 4 + 0.75 * 0 = 4
TEST(SampleSet, KnownSamples) {
  SampleSet s;
  for (double x : {5.0, 9.0, 4.0, 2.0, 4.0, 7.0, 5.0, 4.0}) s.add(x);  // unsorted input
  EXPECT_EQ(s.count(), 8u);
  EXPECT_DOUBLE_EQ(s.sum(), 40.0);
  EXPECT_DOUBLE_EQ(s.mean(), 5.0);
  EXPECT_DOUBLE_EQ(s.population_sd(), 2.0);
  EXPECT_DOUBLE_EQ(s.sd(), std::sqrt(32.0 / 7.0));
  EXPECT_NEAR(s.sd(), 2.1380899352993950, 1e-15);
  EXPECT_NEAR(s.rsd(), 0.42761798705987900, 1e-15);
  EXPECT_DOUBLE_EQ(s.min(), 2.0);
  EXPECT_DOUBLE_EQ(s.max(), 9.0);
  EXPECT_DOUBLE_EQ(s.p50(), 4.5);
  EXPECT_DOUBLE_EQ(s.p90(), 7.6);
  EXPECT_DOUBLE_EQ(s.p99(), 8.86);
  EXPECT_DOUBLE_EQ(s.percentile(25), 4.0);
  EXPECT_DOUBLE_EQ(s.percentile(0), 2.0);
  EXPECT_DOUBLE_EQ(s.percentile(100), 9.0);
  EXPECT_EQ(s.samples().front(), 5.0);  // insertion order is kept
  EXPECT_EQ(s.sorted().front(), 2.0);
}

// 1..10: h(p90) = 9 * 0.9 = 8.1 -> 9 + 0.1 * 1 = 9.1; h(p50) = 4.5 -> 5.5; sample SD =
// sqrt(82.5 / 9) = 3.0276503540974917.
TEST(SampleSet, OneToTen) {
  SampleSet s;
  for (int i = 10; i >= 1; --i) s.add(i);
  EXPECT_DOUBLE_EQ(s.mean(), 5.5);
  EXPECT_DOUBLE_EQ(s.p50(), 5.5);
  EXPECT_DOUBLE_EQ(s.p90(), 9.1);
  EXPECT_NEAR(s.sd(), 3.0276503540974917, 1e-15);
  s.add(100);  // the sorted cache is refreshed after add()
  EXPECT_DOUBLE_EQ(s.max(), 100.0);
  EXPECT_DOUBLE_EQ(s.p50(), 6.0);
}

TEST(SampleSet, UndefinedStatisticsThrow) {
  SampleSet s;
  EXPECT_THROW(s.mean(), std::domain_error);
  EXPECT_THROW(s.p50(), std::domain_error);
  s.add(3.0);
  EXPECT_DOUBLE_EQ(s.mean(), 3.0);
  EXPECT_DOUBLE_EQ(s.p99(), 3.0);
  EXPECT_DOUBLE_EQ(s.population_sd(), 0.0);
  EXPECT_THROW(s.sd(), std::domain_error);  // n - 1 = 0
  EXPECT_THROW(s.percentile(101), std::invalid_argument);
  EXPECT_THROW(s.add(std::nan("")), std::invalid_argument);
  SampleSet zero_mean;
  zero_mean.add(-1);
  zero_mean.add(1);
  EXPECT_THROW(zero_mean.rsd(), std::domain_error);
}

// Busy 1 on [0, 10), 0 on [10, 30), 1 on [30, 40): integral 20 ns, mean over 40 ns = 0.5.
// After reset at 40 and value 3 until 50: mean 3.

}  // namespace
}  // namespace edx::common
