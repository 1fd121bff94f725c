#pragma once
// Simulated time: an unsigned count of picoseconds. Integer time makes event order exact and
// runs reproducible; 2^64 ps is about 213 days of simulated time.
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace edx::sim {

/// Simulated time (or a duration) in integer picoseconds.
using Time = std::uint64_t;

/// The largest representable time; also used as "no limit" by Simulator::run_until.
inline constexpr Time kTimeMax = std::numeric_limits<Time>::max();

/// Simulated time ran out: a time, duration or cycle past 2^64 ps (213 days). Every such check of
/// sim_core throws this type, so that a model can say it in the words of its inputs
/// (simulate_system) without mistaking another error for it.
class TimeRangeError : public std::overflow_error {
 public:
  using std::overflow_error::overflow_error;
};

/// One simulation scheduled more events than the event queue numbers (2^48, event_queue.hpp):
/// like TimeRangeError, a run longer than the model holds, said by the model in its inputs' words.
class EventCountError : public std::length_error {
 public:
  using std::length_error::length_error;
};

namespace detail {
/// value * scale, throwing TimeRangeError instead of wrapping around.
constexpr Time scaled(std::uint64_t value, std::uint64_t scale, const char* overflow_message) {
  if (value > kTimeMax / scale) throw TimeRangeError(overflow_message);
  return value * scale;
}
}  // namespace detail

/// `value` picoseconds.
constexpr Time ps(std::uint64_t value) { return value; }
/// `value` nanoseconds (x 10^3 ps).
constexpr Time ns(std::uint64_t value) {
  return detail::scaled(value, 1'000, "edx::sim: time overflow in ns()");
}
/// `value` microseconds (x 10^6 ps).
constexpr Time us(std::uint64_t value) {
  return detail::scaled(value, 1'000'000, "edx::sim: time overflow in us()");
}
/// `value` milliseconds (x 10^9 ps).
constexpr Time ms(std::uint64_t value) {
  return detail::scaled(value, 1'000'000'000, "edx::sim: time overflow in ms()");
}

/// `value` seconds rounded to the nearest picosecond (halves away from zero); throws
/// std::out_of_range for a negative or NaN value, TimeRangeError for one of 2^64 ps or more.
Time seconds(double value);

/// `t` in seconds (t / 10^12).
constexpr double to_seconds(Time t) { return static_cast<double>(t) * 1e-12; }
/// `t` in milliseconds (t / 10^9).
constexpr double to_ms(Time t) { return static_cast<double>(t) * 1e-9; }
/// `t` in microseconds (t / 10^6).
constexpr double to_us(Time t) { return static_cast<double>(t) * 1e-6; }
/// `t` in nanoseconds (t / 10^3).
constexpr double to_ns(Time t) { return static_cast<double>(t) * 1e-3; }

}  // namespace edx::sim
