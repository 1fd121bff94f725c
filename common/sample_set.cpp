#include "common/sample_set.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace edx::common {

void SampleSet::add(double value) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument("edx::common::SampleSet::add: sample is not a finite number");
  }
  samples_.push_back(value);
  sorted_valid_ = false;
  moments_valid_ = false;
}

void SampleSet::clear() noexcept {
  samples_.clear();
  sorted_.clear();
  sorted_valid_ = moments_valid_ = true;
  mean_ = squared_deviations_ = 0.0;
}

void SampleSet::require(std::size_t minimum, const char* statistic) const {
  if (samples_.size() < minimum) {
    throw std::domain_error(std::string("edx::common::SampleSet::") + statistic +
                            " needs at least " + std::to_string(minimum) + " sample(s), have " +
                            std::to_string(samples_.size()));
  }
}

void SampleSet::update_moments() const {
  if (moments_valid_) return;
  // Two passes: mean first, then the sum of squared deviations from it (numerically stable).
  double sum = 0.0;
  for (double x : samples_) sum += x;
  mean_ = sum / static_cast<double>(samples_.size());
  double squares = 0.0;
  for (double x : samples_) squares += (x - mean_) * (x - mean_);
  squared_deviations_ = squares;
  moments_valid_ = true;
}

double SampleSet::sum() const {
  double sum = 0.0;
  for (double x : samples_) sum += x;
  return sum;
}

double SampleSet::mean() const {
  require(1, "mean");
  update_moments();
  return mean_;
}

double SampleSet::sd() const {
  require(2, "sd");
  update_moments();
  return std::sqrt(squared_deviations_ / static_cast<double>(samples_.size() - 1));
}

double SampleSet::population_sd() const {
  require(1, "population_sd");
  update_moments();
  return std::sqrt(squared_deviations_ / static_cast<double>(samples_.size()));
}

double SampleSet::rsd() const {
  const double deviation = sd();
  const double average = mean();
  if (average == 0.0) throw std::domain_error("edx::common::SampleSet::rsd: the mean is zero");
  return deviation / average;
}

const std::vector<double>& SampleSet::sorted() const {
  if (!sorted_valid_) {
    sorted_ = samples_;
    std::sort(sorted_.begin(), sorted_.end());
    sorted_valid_ = true;
  }
  return sorted_;
}

double SampleSet::min() const {
  require(1, "min");
  return sorted().front();
}

double SampleSet::max() const {
  require(1, "max");
  return sorted().back();
}

double SampleSet::percentile(double p) const {
  require(1, "percentile");
  if (!(p >= 0.0 && p <= 100.0)) {
    throw std::invalid_argument("edx::common::SampleSet::percentile(" + std::to_string(p) +
                                "): expected 0 <= p <= 100");
  }
  const std::vector<double>& x = sorted();
  // h = (n - 1) p / 100; interpolate between x[floor h] and x[floor h + 1].
  const double h = static_cast<double>(x.size() - 1) * p / 100.0;
  const auto lower = static_cast<std::size_t>(std::floor(h));
  const double fraction = h - static_cast<double>(lower);
  if (fraction == 0.0 || lower + 1 >= x.size()) return x[lower];
  return x[lower] + fraction * (x[lower + 1] - x[lower]);
}

// ------------------------------------------------------------------------------- TimeWeighted

}  // namespace edx::common
