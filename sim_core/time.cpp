#include "sim_core/time.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace edx::sim {

Time seconds(double value) {
  // 2^64 ps as a double; anything at or above it cannot be represented.
  constexpr double kLimitPs = 18446744073709551616.0;
  const double picoseconds = std::round(value * 1e12);
  if (std::isnan(value) || value < 0.0 || picoseconds >= kLimitPs) {
    // The value in a few digits: 1e308 printed in full is 309 digits (issue 45).
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    const std::string message = std::string("a duration of ") + text +
                                " s: expected a finite, non-negative duration below 2^64 ps "
                                "(213 days)";
    if (std::isnan(value) || value < 0.0) throw std::out_of_range(message);
    throw TimeRangeError(message);  // +inf included
  }
  return static_cast<Time>(picoseconds);
}

}  // namespace edx::sim
