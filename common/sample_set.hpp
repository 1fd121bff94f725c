#pragma once
// A set of samples with exact statistics (plain numbers, no simulator): mean, SD, percentiles.
//
// Definitions (docs/SIM_CORE.md, "Statistics"):
//   mean       = (1/n) * sum x_i
//   sd         = sqrt( sum (x_i - mean)^2 / (n - 1) )    sample SD (Bessel), needs n >= 2
//   population_sd = sqrt( sum (x_i - mean)^2 / n )
//   rsd        = sd / mean                               (relative SD, a fraction, not percent)
//   percentile(p), p in [0, 100]: linear interpolation between closest ranks, numpy's default
//              ("linear", type 7 of Hyndman & Fan): with the samples sorted x_0 <= ... <= x_{n-1},
//              h = (n - 1) * p / 100, percentile = x_floor(h) + (h - floor(h)) * (x_ceil(h) -
//              x_floor(h)).
#include <cstddef>
#include <vector>

namespace edx::common {

/// All samples of a quantity, kept so that percentiles are exact. Undefined statistics (mean of
/// no samples, SD of fewer than two, RSD with a zero mean) throw std::domain_error.
class SampleSet {
 public:
  /// Adds one sample; throws std::invalid_argument for NaN or infinity.
  void add(double value);
  /// Reserves room for `n` samples.
  void reserve(std::size_t n) { samples_.reserve(n); }
  /// Drops all samples.
  void clear() noexcept;

  /// Number of samples.
  std::size_t count() const noexcept { return samples_.size(); }
  /// True when no sample was added.
  bool empty() const noexcept { return samples_.empty(); }
  /// Sum of the samples.
  double sum() const;
  /// Arithmetic mean (n >= 1).
  double mean() const;
  /// Sample standard deviation, divisor n - 1 (n >= 2).
  double sd() const;
  /// Population standard deviation, divisor n (n >= 1).
  double population_sd() const;
  /// Relative standard deviation sd() / mean() (n >= 2, mean != 0).
  double rsd() const;
  /// Smallest sample (n >= 1).
  double min() const;
  /// Largest sample (n >= 1).
  double max() const;
  /// Linear-interpolation percentile, p in [0, 100] (n >= 1); see the top of stats.hpp.
  double percentile(double p) const;
  /// Median, percentile(50).
  double p50() const { return percentile(50.0); }
  /// percentile(90).
  double p90() const { return percentile(90.0); }
  /// percentile(99).
  double p99() const { return percentile(99.0); }

  /// Samples in insertion order.
  const std::vector<double>& samples() const noexcept { return samples_; }
  /// Samples in ascending order (computed lazily, cached until the next add()).
  const std::vector<double>& sorted() const;

 private:
  void require(std::size_t minimum, const char* statistic) const;
  void update_moments() const;

  std::vector<double> samples_;
  mutable std::vector<double> sorted_;
  mutable bool sorted_valid_ = true;
  mutable bool moments_valid_ = true;
  mutable double mean_ = 0.0;
  mutable double squared_deviations_ = 0.0;  ///< sum (x_i - mean)^2, two-pass
};

}  // namespace edx::common
