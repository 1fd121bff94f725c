#include "sim_core/time.hpp"

#include <cmath>
#include <string>

namespace edx::sim {

Time seconds(double value) {
  // 2^64 ps as a double; anything at or above it cannot be represented.
  constexpr double kLimitPs = 18446744073709551616.0;
  const double picoseconds = std::round(value * 1e12);
  if (!std::isfinite(value) || value < 0.0 || picoseconds >= kLimitPs) {
    throw std::out_of_range("edx::sim::seconds(" + std::to_string(value) +
                            "): expected a finite, non-negative duration below 2^64 ps");
  }
  return static_cast<Time>(picoseconds);
}

}  // namespace edx::sim
