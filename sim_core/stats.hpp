#pragma once
// Statistics: counters, sample sets with exact percentiles, time-weighted averages, and a
// registry that names them hierarchically and dumps them.
//
// Definitions (see docs/SIM_CORE.md):
//   mean       = (1/n) * sum x_i
//   sd         = sqrt( sum (x_i - mean)^2 / (n - 1) )    sample SD (Bessel), needs n >= 2
//   population_sd = sqrt( sum (x_i - mean)^2 / n )
//   rsd        = sd / mean                               (relative SD, a fraction, not percent)
//   percentile(p), p in [0, 100]: linear interpolation between closest ranks, numpy's default
//              ("linear", type 7 of Hyndman & Fan): with the samples sorted x_0 <= ... <= x_{n-1},
//              h = (n - 1) * p / 100, percentile = x_floor(h) + (h - floor(h)) * (x_ceil(h) -
//              x_floor(h)).
//   time-weighted mean over [t0, now] = (1 / (now - t0)) * integral of value(t) dt.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/sample_set.hpp"
#include "sim_core/simulator.hpp"
#include "sim_core/time.hpp"

namespace edx::sim {

/// A monotonically increasing event count.
class Counter {
 public:
  /// Adds `n` (default 1).
  void add(std::uint64_t n = 1) noexcept { value_ += n; }
  /// Adds 1.
  Counter& operator++() noexcept {
    ++value_;
    return *this;
  }
  /// Current count.
  std::uint64_t value() const noexcept { return value_; }
  /// Back to zero.
  void reset() noexcept { value_ = 0; }

 private:
  std::uint64_t value_ = 0;
};

/// Samples with exact percentiles (common/sample_set.hpp; plain statistics, used outside the
/// simulator too).
using SampleSet = common::SampleSet;

/// A piecewise-constant quantity over simulated time (units busy, FIFO occupancy, ...) and its
/// time integral. The averaging window starts at construction (or reset()) and ends at now().
class TimeWeighted {
 public:
  /// Starts the window at sim.now() with value `initial`.
  explicit TimeWeighted(const Simulator& sim, double initial = 0.0);

  /// The quantity takes `value` from now on.
  void set(double value);
  /// set(current() + delta).
  void add(double delta) { set(current_ + delta); }
  /// set(value) as if called at `when`, a time already past: for a model that computed a change
  /// instead of living through it (Resource::book_idle). Requires last change <= when <= now();
  /// std::logic_error otherwise. The same arithmetic as set(), so the same integral.
  void set_at(Time when, double value);
  /// Restarts the window at now() keeping the current value (e.g. after a warm-up).
  void reset();

  /// Current value.
  double current() const noexcept { return current_; }
  /// Largest value held in the window.
  double max() const noexcept { return max_; }
  /// Integral of the value over the window, in value x picoseconds.
  double integral() const;
  /// When the value last changed (set, set_at, reset or construction).
  Time last_change() const noexcept { return last_change_; }
  /// Length of the window, now() - start.
  Time elapsed() const;
  /// Time-weighted mean integral() / elapsed(); throws std::domain_error for an empty window.
  double mean() const;

 private:
  const Simulator* sim_;
  double current_;
  double max_;
  Time start_;
  Time last_change_;
  double area_ = 0.0;  ///< integral over [start_, last_change_]
};

/// Statistics registered by reference under hierarchical dot-separated names
/// ("frontend.fd.latency"). The registered objects must outlive the registry's dumps.
class StatsRegistry {
 public:
  /// Registers a counter. Names must be non-empty dot-separated segments, unique, and neither a
  /// prefix segment path of another name nor extended by one; violations throw
  /// std::invalid_argument.
  void add(const std::string& name, const Counter& counter);
  /// Registers a sample set.
  void add(const std::string& name, const SampleSet& samples);
  /// Registers a time-weighted quantity.
  void add(const std::string& name, const TimeWeighted& quantity);
  /// Registers a value computed on demand (e.g. a utilization).
  void add_gauge(const std::string& name, std::function<double()> gauge);

  /// Number of registered statistics.
  std::size_t size() const noexcept { return entries_.size(); }
  /// True if `name` is registered.
  bool contains(const std::string& name) const { return entries_.count(name) != 0; }

  /// Nested JSON object following the name segments. Counter -> integer; gauge -> number;
  /// SampleSet -> {count, mean, sd, rsd, min, p50, p90, p99, max}; TimeWeighted ->
  /// {mean, max, current, elapsed_ps}. Undefined statistics are null.
  nlohmann::json to_json() const;
  /// Flat name -> value listing sorted by name: counters and gauges under their own name,
  /// fields of the others as "<name>.<field>". Undefined statistics are left out.
  std::vector<std::pair<std::string, double>> to_listing() const;
  /// to_listing() as text, one "name value" line each.
  std::string to_text() const;

 private:
  using Entry =
      std::variant<const Counter*, const SampleSet*, const TimeWeighted*, std::function<double()>>;
  void insert(const std::string& name, Entry entry);

  std::map<std::string, Entry> entries_;
};

}  // namespace edx::sim
