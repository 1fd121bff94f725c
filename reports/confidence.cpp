#include "reports/confidence.hpp"

#include <fmt/format.h>

#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <stdexcept>

namespace edx::reports {

Interval student_t_interval(std::span<const double> samples, const std::string& figure,
                            double confidence) {
  if (!(confidence > 0 && confidence < 1)) {
    throw std::invalid_argument(
        fmt::format("{}: confidence {} is not in (0, 1)", figure, confidence));
  }
  if (samples.empty()) throw std::runtime_error(fmt::format("{}: no samples", figure));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!std::isfinite(samples[i])) {
      throw std::runtime_error(fmt::format("{}: sample {} of {} is not finite ({})", figure, i + 1,
                                           samples.size(), samples[i]));
    }
  }
  const double n = static_cast<double>(samples.size());
  double sum = 0;
  for (double x : samples) sum += x;
  Interval interval;
  interval.n = static_cast<int>(samples.size());
  interval.mean = interval.low = interval.high = sum / n;
  if (!interval.has_spread()) return interval;
  double squares = 0;
  for (double x : samples) squares += (x - interval.mean) * (x - interval.mean);
  const double sd = std::sqrt(squares / (n - 1));
  const boost::math::students_t t(n - 1);
  const double half = boost::math::quantile(t, 1 - (1 - confidence) / 2) * sd / std::sqrt(n);
  interval.low = interval.mean - half;
  interval.high = interval.mean + half;
  return interval;
}

bool within_tolerance(double relative_error, double tolerance) {
  return std::abs(relative_error) <= tolerance + 1e-12;
}

const char* to_string(IntervalVerdict v) {
  switch (v) {
    case IntervalVerdict::kInside:
      return "inside";
    case IntervalVerdict::kAcross:
      return "across";
    case IntervalVerdict::kOutside:
      break;
  }
  return "outside";
}

IntervalVerdict interval_verdict(const Interval& interval, double paper, double tolerance) {
  const double low = (interval.low - paper) / std::abs(paper);
  const double high = (interval.high - paper) / std::abs(paper);
  const bool low_in = within_tolerance(low, tolerance);
  const bool high_in = within_tolerance(high, tolerance);
  if (low_in && high_in) return IntervalVerdict::kInside;
  // Both ends beyond the same edge: disjoint. Beyond opposite edges: the interval spans the band.
  if (!low_in && !high_in && (low > 0) == (high > 0)) return IntervalVerdict::kOutside;
  return IntervalVerdict::kAcross;
}

}  // namespace edx::reports
