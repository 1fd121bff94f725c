// Time units and clock domains: exact cycle <-> time conversion with the ceil rounding rule.
#include "sim_core/clock.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>

#include "sim_core/time.hpp"

namespace edx::sim {
namespace {

TEST(Time, UnitHelpersScaleToPicoseconds) {
  EXPECT_EQ(ps(7), 7u);
  EXPECT_EQ(ns(3), 3'000u);
  EXPECT_EQ(us(2), 2'000'000u);
  EXPECT_EQ(ms(5), 5'000'000'000u);
  EXPECT_EQ(seconds(1.5), 1'500'000'000'000u);
  EXPECT_EQ(seconds(3e-12), 3u);
  EXPECT_EQ(seconds(1e-9), ns(1));
  EXPECT_DOUBLE_EQ(to_us(ns(1500)), 1.5);
  EXPECT_DOUBLE_EQ(to_seconds(ms(250)), 0.25);
  static_assert(ns(1) == 1000, "usable in constant expressions");
}

TEST(Time, OverflowAndBadValuesThrow) {
  EXPECT_THROW(ns(kTimeMax / 999), std::overflow_error);
  EXPECT_THROW(seconds(-1.0), std::out_of_range);
  EXPECT_THROW(seconds(1e8), TimeRangeError);  // 10^20 ps > 2^64
}

// 150 MHz: period 10^12 / 1.5e8 = 6666.67 ps. Edge n at ceil(n * 20000 / 3).
TEST(ClockDomain, OneHundredFiftyMegahertzHasNoDrift) {
  const ClockDomain clock("fpga", 150.0);
  EXPECT_EQ(clock.name(), "fpga");
  EXPECT_DOUBLE_EQ(clock.frequency_mhz(), 150.0);
  EXPECT_EQ(clock.time_of_cycles(0), 0u);
  EXPECT_EQ(clock.time_of_cycles(1), 6667u);         // ceil(6666.67)
  EXPECT_EQ(clock.time_of_cycles(2), 13334u);        // ceil(13333.33)
  EXPECT_EQ(clock.time_of_cycles(3), 20000u);        // exact
  EXPECT_EQ(clock.time_of_cycles(150), 1'000'000u);  // 1 us
  // 1000 cycles: ceil(6666666.67) = 6666667, not 1000 * 6667 = 6667000 (rounded-period drift).
  EXPECT_EQ(clock.time_of_cycles(1000), 6'666'667u);
  EXPECT_EQ(clock.time_of_cycles(150'000'000), 1'000'000'000'000u);  // 1 s

  EXPECT_EQ(clock.cycles_in(6666), 0u);
  EXPECT_EQ(clock.cycles_in(6667), 1u);
  EXPECT_EQ(clock.cycles_in(19999), 2u);
  EXPECT_EQ(clock.cycles_in(20000), 3u);
  EXPECT_EQ(clock.next_edge(0), 0u);
  EXPECT_EQ(clock.next_edge(1), 6667u);
  EXPECT_EQ(clock.next_edge(6667), 6667u);
  EXPECT_EQ(clock.next_edge(6668), 13334u);
}

// Either side of 2^64 for the products n * 20000 and t * 3 (150 MHz): the 64-bit path below, the
// 128-bit one above, the same rounding rule (values by exact integer arithmetic).
TEST(ClockDomain, ProductsEitherSideOfTwoToTheSixtyFourRoundAlike) {
  const ClockDomain clock("fpga", 150.0);
  // n0 = floor((2^64 - 1) / 20000): n0 * 20000 = 18446744073709540000 fits in 64 bits.
  const std::uint64_t n0 = 922'337'203'685'477;
  EXPECT_EQ(clock.time_of_cycles(n0), 6'148'914'691'236'513'334u);      // ceil(.../3)
  EXPECT_EQ(clock.time_of_cycles(n0 + 1), 6'148'914'691'236'520'000u);  // 128-bit, exact
  // t * 3 fits for the first edge, not for the second.
  EXPECT_EQ(clock.cycles_in(6'148'914'691'236'513'334u), n0);
  EXPECT_EQ(clock.cycles_in(6'148'914'691'236'520'000u), n0 + 1);
  EXPECT_EQ(clock.cycles_in(6'148'914'691'236'519'999u), n0);
  EXPECT_EQ(clock.next_edge(6'148'914'691'236'513'335u), 6'148'914'691'236'520'000u);
}

// 333 MHz: period 10^6 / 333 ps = 3003.003 ps.
TEST(ClockDomain, ThreeHundredThirtyThreeMegahertz) {
  const ClockDomain clock("backend", 333.0);
  EXPECT_EQ(clock.time_of_cycles(1), 3004u);          // ceil(3003.003)
  EXPECT_EQ(clock.time_of_cycles(333), 1'000'000u);   // exactly 1 us
  EXPECT_EQ(clock.time_of_cycles(1000), 3'003'004u);  // ceil(3003003.003)
  EXPECT_EQ(clock.cycles_in(999'999), 332u);
  EXPECT_EQ(clock.cycles_in(1'000'000), 333u);
  EXPECT_NEAR(clock.period_ps(), 3003.003003003003, 1e-9);
}

TEST(ClockDomain, EdgesMatchTheClosedFormForManyCycles) {
  // Independent closed forms with small integers: 150 MHz -> ceil(20000 n / 3);
  // 333 MHz -> ceil(10^6 n / 333). Also cycles_in inverts time_of_cycles on every edge.
  const ClockDomain fast("fast", 150.0);
  const ClockDomain odd("odd", 333.0);
  for (std::uint64_t n = 0; n < 200'000; n += 7) {
    ASSERT_EQ(fast.time_of_cycles(n), (20000 * n + 2) / 3) << n;
    ASSERT_EQ(odd.time_of_cycles(n), (1'000'000 * n + 332) / 333) << n;
    ASSERT_EQ(fast.cycles_in(fast.time_of_cycles(n)), n);
    ASSERT_EQ(odd.cycles_in(odd.time_of_cycles(n)), n);
    if (n > 0) {
      ASSERT_EQ(odd.cycles_in(odd.time_of_cycles(n) - 1), n - 1);
    }
  }
}

TEST(ClockDomain, FromPeriodAndFromHz) {
  const ClockDomain three_ns = ClockDomain::from_period("sb", 3000);
  EXPECT_EQ(three_ns.time_of_cycles(7), 21000u);
  EXPECT_EQ(three_ns.cycles_in(20999), 6u);
  EXPECT_NEAR(three_ns.frequency_mhz(), 333.3333333333, 1e-9);

  const ClockDomain rounded("r", 333.333333);                          // rounds to 333333333 Hz
  EXPECT_EQ(rounded.time_of_cycles(333'333'333), 1'000'000'000'000u);  // 1 s exactly
  EXPECT_EQ(rounded.time_of_cycles(1), 3001u);                         // ceil(3000.000003)

  const ClockDomain hz = ClockDomain::from_hz("pcie", 250'000'000);
  EXPECT_EQ(hz.time_of_cycles(5), 20000u);
  EXPECT_EQ(hz.period_numerator(), 4000u);
  EXPECT_EQ(hz.period_denominator(), 1u);
}

TEST(ClockDomain, RejectsBadFrequencies) {
  EXPECT_THROW(ClockDomain("zero", 0.0), std::invalid_argument);
  EXPECT_THROW(ClockDomain("negative", -5.0), std::invalid_argument);
  EXPECT_THROW(ClockDomain("too_fast", 2e6), std::invalid_argument);  // 2 THz
  EXPECT_THROW(ClockDomain::from_period("zero", 0), std::invalid_argument);
  EXPECT_THROW(ClockDomain::from_hz("zero", 0), std::invalid_argument);
  EXPECT_THROW(ClockDomain::from_period("slow", kTimeMax / 2).time_of_cycles(3),
               std::overflow_error);
}

}  // namespace
}  // namespace edx::sim
