#pragma once
// How sure a figure is over several runs of the same workload (seeds, issue 43): the 95 %
// two-sided Student-t confidence interval of its mean, and where that interval lies against a
// paper target's tolerance band (docs/REPORTS.md, "Confidence intervals").
//
//   mean ± t_{0.975, n−1} · s / √n,  s the sample standard deviation (divisor n − 1),
//
// t the Student-t quantile with n − 1 degrees of freedom (Boost.Math students_t; e.g.
// t_{0.975,2} = 4.302653, t_{0.975,4} = 2.776445). The interval assumes the runs are independent
// draws of a roughly normal figure; with few seeds it is wide, as it should be.
#include <span>
#include <string>

namespace edx::reports {

/// A figure's mean over n runs and its confidence interval [low, high].
struct Interval {
  double mean = 0, low = 0, high = 0;
  int n = 0;  ///< the number of runs (samples)
  /// False for one run: nothing to estimate a spread from, so the interval is the point itself
  /// (low = high = mean); it says nothing of how far another seed would move the figure.
  bool has_spread() const { return n > 1; }
};

/// The two-sided Student-t interval at `confidence` (0.95: 95 %) of the mean of `samples`.
/// Throws std::runtime_error naming `figure` when there are no samples or one is not finite
/// ("<figure>: sample 2 of 3 is not finite (nan)"), and std::invalid_argument for a confidence
/// outside (0, 1).
Interval student_t_interval(std::span<const double> samples, const std::string& figure,
                            double confidence = 0.95);

/// Whether a relative error (value − paper) / |paper| is within `tolerance`, edges included with
/// a 1e-12 slack so that a value exactly on the edge passes despite rounding. The one rule of the
/// paper check's pass and of the interval verdicts.
bool within_tolerance(double relative_error, double tolerance);

/// Where an interval lies against a target's tolerance band [paper − tol·|paper|,
/// paper + tol·|paper|] (edges included, as a pass of the mean): kInside, the whole interval
/// within the band; kAcross, it overlaps a band edge (some seeds' means would pass, some miss);
/// kOutside, disjoint from the band.
enum class IntervalVerdict { kInside, kAcross, kOutside };
/// "inside", "across", "outside".
const char* to_string(IntervalVerdict v);

/// The verdict of `interval` against the band of `paper` (non-zero) and relative `tolerance`.
IntervalVerdict interval_verdict(const Interval& interval, double paper, double tolerance);

}  // namespace edx::reports
