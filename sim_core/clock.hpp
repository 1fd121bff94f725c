#pragma once
// Clock domains: exact conversion between cycle counts and picosecond time.
//
// Rounding rule. A clock of frequency f (Hz) has its n-th rising edge at the exact instant
// n / f seconds = n * 10^12 / f ps. Edge n is placed at the first whole picosecond not before
// that instant:
//
//     time_of_cycles(n) = ceil(n * 10^12 / f)          (integer, 128-bit intermediate)
//     cycles_in(t)      = floor(t * f / 10^12)         = number of edges in (0, t]
//
// Each edge time is computed from n directly, never by adding a rounded period, so n cycles never
// accumulate drift (150 MHz: 1 cycle = 6667 ps, 3 cycles = 20000 ps exactly). Because edges are
// rounded up, the two functions are exact inverses on edges: cycles_in(time_of_cycles(n)) == n,
// and cycles_in(t) is the largest n with time_of_cycles(n) <= t. Frequencies above 1 THz
// (periods shorter than 1 ps) are rejected because edges would collide.
#include <cstdint>
#include <string>

#include "sim_core/time.hpp"

namespace edx::sim {

/// A named clock with an exact rational period (see the rounding rule at the top of clock.hpp).
class ClockDomain {
 public:
  /// A clock of `frequency_mhz` MHz, rounded to the nearest whole Hz (333.333333 MHz ->
  /// 333333333 Hz). Throws std::invalid_argument unless 1 Hz <= f <= 1 THz.
  ClockDomain(std::string name, double frequency_mhz);

  /// A clock of exactly `frequency_hz` Hz (1 <= f <= 10^12).
  static ClockDomain from_hz(std::string name, std::uint64_t frequency_hz);
  /// A clock whose period is exactly `period` picoseconds (>= 1), e.g. 3000 ps for "333 MHz"
  /// meant as a 3 ns period.
  static ClockDomain from_period(std::string name, Time period);

  /// The name given at construction.
  const std::string& name() const { return name_; }
  /// Frequency in Hz (10^12 / period; exact as a ratio, rounded here to a double).
  double frequency_hz() const;
  /// Frequency in MHz.
  double frequency_mhz() const { return frequency_hz() * 1e-6; }
  /// Period in picoseconds as a double (the exact period is period_numerator/period_denominator).
  double period_ps() const;
  /// Period = period_numerator() / period_denominator() picoseconds, in lowest terms.
  std::uint64_t period_numerator() const { return period_num_; }
  /// See period_numerator().
  std::uint64_t period_denominator() const { return period_den_; }

  /// Time of rising edge n: ceil(n * period) ps. Edge 0 is at time 0. Throws TimeRangeError
  /// when the edge lies beyond kTimeMax.
  Time time_of_cycles(std::uint64_t n) const {
    // ceil(n * num / den) in 64 bits when n * num + den - 1 fits (150 MHz: num 20000, n < 9.2e14:
    // the usual case, inline), else with a 128-bit product (wide_time_of_cycles): the same
    // integer.
    std::uint64_t narrow = 0;
    if (!__builtin_mul_overflow(n, period_num_, &narrow) && narrow <= kTimeMax - (period_den_ - 1))
        [[likely]] {
      return (narrow + period_den_ - 1) / period_den_;
    }
    return wide_time_of_cycles(n);
  }
  /// Number of complete cycles (rising edges) in (0, t]: floor(t / period).
  std::uint64_t cycles_in(Time t) const {
    // floor(t * den / num); den <= 10^12 so the product stays below 2^104 (in 64 bits when it
    // fits there, inline: the same integer).
    std::uint64_t narrow = 0;
    if (!__builtin_mul_overflow(t, period_den_, &narrow)) [[likely]] {
      return narrow / period_num_;
    }
    return wide_cycles_in(t);
  }
  /// The first edge at or after `t` (t itself when t is an edge).
  Time next_edge(Time t) const {
    const std::uint64_t n = cycles_in(t);
    const Time edge = time_of_cycles(n);
    return edge == t ? t : time_of_cycles(n + 1);
  }

 private:
  /// time_of_cycles with a 128-bit product; throws TimeRangeError beyond kTimeMax.
  Time wide_time_of_cycles(std::uint64_t n) const;
  /// cycles_in with a 128-bit product.
  std::uint64_t wide_cycles_in(Time t) const;

  ClockDomain(std::string name, std::uint64_t period_num, std::uint64_t period_den);

  std::string name_;
  std::uint64_t period_num_;  ///< period = period_num_ / period_den_ ps, gcd 1
  std::uint64_t period_den_;
};

}  // namespace edx::sim
