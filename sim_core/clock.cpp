#include "sim_core/clock.hpp"

#include <cmath>
#include <numeric>
#include <stdexcept>

namespace edx::sim {
namespace {

using Wide = unsigned __int128;

constexpr std::uint64_t kPsPerSecond = 1'000'000'000'000ULL;

}  // namespace

ClockDomain::ClockDomain(std::string name, std::uint64_t period_num, std::uint64_t period_den)
    : name_(std::move(name)) {
  const std::uint64_t g = std::gcd(period_num, period_den);
  period_num_ = period_num / g;
  period_den_ = period_den / g;
}

ClockDomain::ClockDomain(std::string name, double frequency_mhz)
    : ClockDomain(from_hz(name, [&] {
        const double hz = std::round(frequency_mhz * 1e6);
        if (!std::isfinite(frequency_mhz) || hz < 1.0 || hz > static_cast<double>(kPsPerSecond)) {
          throw std::invalid_argument("clock '" + name + "': frequency " +
                                      std::to_string(frequency_mhz) +
                                      " MHz out of range (expected 1e-6 .. 1e6 MHz)");
        }
        return static_cast<std::uint64_t>(hz);
      }())) {}

ClockDomain ClockDomain::from_hz(std::string name, std::uint64_t frequency_hz) {
  if (frequency_hz < 1 || frequency_hz > kPsPerSecond) {
    throw std::invalid_argument("clock '" + name + "': frequency " + std::to_string(frequency_hz) +
                                " Hz out of range (expected 1 .. 1e12 Hz)");
  }
  // period = 10^12 / f ps.
  return ClockDomain(std::move(name), kPsPerSecond, frequency_hz);
}

ClockDomain ClockDomain::from_period(std::string name, Time period) {
  if (period < 1) {
    throw std::invalid_argument("clock '" + name + "': period must be at least 1 ps");
  }
  return ClockDomain(std::move(name), period, 1);
}

double ClockDomain::frequency_hz() const {
  return static_cast<double>(kPsPerSecond) * static_cast<double>(period_den_) /
         static_cast<double>(period_num_);
}

double ClockDomain::period_ps() const {
  return static_cast<double>(period_num_) / static_cast<double>(period_den_);
}

Time ClockDomain::wide_time_of_cycles(std::uint64_t n) const {
  // n < 2^64 and num <= 2^64: the product cannot overflow 2^128.
  const Wide product = static_cast<Wide>(n) * period_num_;
  const Wide edge = (product + period_den_ - 1) / period_den_;
  if (edge > kTimeMax) {
    throw TimeRangeError("clock '" + name_ + "': cycle " + std::to_string(n) +
                         " lies beyond the largest representable time");
  }
  return static_cast<Time>(edge);
}

std::uint64_t ClockDomain::wide_cycles_in(Time t) const {
  return static_cast<std::uint64_t>(static_cast<Wide>(t) * period_den_ / period_num_);
}

}  // namespace edx::sim
