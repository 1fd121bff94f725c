// The Student-t confidence intervals of reports/confidence and the paper check over several runs
// (check_targets_over_runs), against values computed by hand: t quantiles from a Student-t table
// (t_{0.975,2} = 4.302653, t_{0.975,4} = 2.776445).
#include "reports/confidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "reports/paper_check.hpp"

namespace edx::reports {
namespace {

TEST(ConfidenceInterval, ThreeSamplesByHand) {
  // mean 2, s = sqrt(((−1)² + 0 + 1²) / 2) = 1, half-width 4.302653 · 1 / √3 = 2.484138.
  const std::vector<double> samples = {1, 2, 3};
  const Interval i = student_t_interval(samples, "figure");
  EXPECT_EQ(i.n, 3);
  EXPECT_TRUE(i.has_spread());
  EXPECT_DOUBLE_EQ(i.mean, 2.0);
  EXPECT_NEAR(i.high - i.mean, 2.484138, 1e-6);
  EXPECT_NEAR(i.mean - i.low, 2.484138, 1e-6);
}

TEST(ConfidenceInterval, FiveSamplesByHand) {
  // mean 14, s = sqrt((16 + 4 + 0 + 4 + 16) / 4) = 3.162278, half 2.776445 · 3.162278 / √5
  // = 3.926486.
  const std::vector<double> samples = {10, 12, 14, 16, 18};
  const Interval i = student_t_interval(samples, "figure");
  EXPECT_EQ(i.n, 5);
  EXPECT_DOUBLE_EQ(i.mean, 14.0);
  EXPECT_NEAR(i.low, 14 - 3.926486, 1e-5);
  EXPECT_NEAR(i.high, 14 + 3.926486, 1e-5);
  // A lower confidence narrows it: t_{0.95,4} = 2.131847.
  const Interval ninety = student_t_interval(samples, "figure", 0.90);
  EXPECT_NEAR(ninety.high - ninety.mean, 2.131847 * std::sqrt(10.0) / std::sqrt(5.0), 1e-5);
}

TEST(ConfidenceInterval, OneSampleIsThePointWithoutSpread) {
  const std::vector<double> samples = {7.5};
  const Interval i = student_t_interval(samples, "figure");
  EXPECT_EQ(i.n, 1);
  EXPECT_FALSE(i.has_spread());
  EXPECT_DOUBLE_EQ(i.mean, 7.5);
  EXPECT_DOUBLE_EQ(i.low, 7.5);
  EXPECT_DOUBLE_EQ(i.high, 7.5);
}

TEST(ConfidenceInterval, EqualSamplesHaveAZeroWidthInterval) {
  const std::vector<double> samples = {3, 3, 3, 3};
  const Interval i = student_t_interval(samples, "figure");
  EXPECT_TRUE(i.has_spread());  // four runs: a spread estimated, and it is 0
  EXPECT_DOUBLE_EQ(i.low, 3.0);
  EXPECT_DOUBLE_EQ(i.high, 3.0);
}

TEST(ConfidenceInterval, BadSamplesAreErrorsNamingTheFigure) {
  const auto error_of = [](std::vector<double> samples, double confidence = 0.95) {
    try {
      student_t_interval(samples, "e2e speedup overall", confidence);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_of({1, std::numeric_limits<double>::quiet_NaN(), 3}),
            "e2e speedup overall: sample 2 of 3 is not finite (nan)");
  EXPECT_EQ(error_of({std::numeric_limits<double>::infinity()}),
            "e2e speedup overall: sample 1 of 1 is not finite (inf)");
  EXPECT_EQ(error_of({}), "e2e speedup overall: no samples");
  EXPECT_EQ(error_of({1, 2}, 1.0), "e2e speedup overall: confidence 1 is not in (0, 1)");
}

Interval interval(double low, double high) { return {(low + high) / 2, low, high, 3}; }

TEST(IntervalVerdict, InsideAcrossOutsideTheBand) {
  // paper 2, tolerance 10 %: the band is [1.8, 2.2].
  const auto verdict = [](double low, double high) {
    return interval_verdict(interval(low, high), 2.0, 0.10);
  };
  EXPECT_EQ(verdict(1.9, 2.1), IntervalVerdict::kInside);
  EXPECT_EQ(verdict(1.8, 2.2), IntervalVerdict::kInside);  // the edges belong to the band
  EXPECT_EQ(verdict(1.7, 1.9), IntervalVerdict::kAcross);  // over the lower edge
  EXPECT_EQ(verdict(2.1, 2.3), IntervalVerdict::kAcross);  // over the upper edge
  EXPECT_EQ(verdict(1.5, 2.5), IntervalVerdict::kAcross);  // the band inside the interval
  EXPECT_EQ(verdict(2.2, 2.4), IntervalVerdict::kAcross);  // touching the edge
  EXPECT_EQ(verdict(2.3, 2.5), IntervalVerdict::kOutside);
  EXPECT_EQ(verdict(1.0, 1.7), IntervalVerdict::kOutside);
  // A negative paper value: the band is [−1.1, −0.9].
  EXPECT_EQ(interval_verdict(interval(-1.05, -0.95), -1.0, 0.10), IntervalVerdict::kInside);
  EXPECT_EQ(interval_verdict(interval(-0.95, -0.5), -1.0, 0.10), IntervalVerdict::kAcross);
  EXPECT_EQ(interval_verdict(interval(-0.85, -0.5), -1.0, 0.10), IntervalVerdict::kOutside);
  EXPECT_STREQ(to_string(IntervalVerdict::kAcross), "across");
}

/// A metric tree with an overall e2e speedup and a kernel speedup, of a run with SLAM frames only.
nlohmann::json slam_run(double speedup, std::optional<double> kernel_speedup = {}) {
  nlohmann::json tree = {
      {"system",
       {{"comparison", {{"all", {{"e2e_speedup", speedup}}}, {"slam", {{"e2e_speedup", speedup}}}}},
        {"baseline", {{"modes", {{"all", {{"frames", 4}}}, {"slam", {{"frames", 4}}}}}}}}}};
  if (kernel_speedup) tree["derived"]["kernels"]["marginalization"]["speedup"] = *kernel_speedup;
  return tree;
}

PaperTarget target(std::string name, std::string metric, double paper) {
  PaperTarget t;
  t.name = std::move(name);
  t.metric = std::move(metric);
  t.paper = paper;
  t.tolerance = 0.10;
  return t;
}

TEST(CheckOverRuns, MeanIntervalAndVerdictsPerTarget) {
  const std::vector<PaperTarget> targets = {
      target("spread", "system.comparison.all.e2e_speedup", 2.0),        // runs 1, 2, 3
      target("far", "system.comparison.slam.e2e_speedup", 10.0),         // runs 1, 2, 3
      target("kernel", "derived.kernels.marginalization.speedup", 2.0),  // 1.98, 2.0, 2.02
      target("VIO", "system.comparison.vio.e2e_speedup", 2.1),           // no VIO frames
      target("missing", "derived.kernels.marginalization.latency_reduction", 0.5)};
  const std::vector<nlohmann::json> runs = {slam_run(1, 1.98), slam_run(2, 2.0), slam_run(3, 2.02)};
  const CheckResult c = check_targets_over_runs(targets, runs, {"r1", "r2", "r3"});
  ASSERT_EQ(c.rows.size(), 5u);
  EXPECT_EQ(c.runs, 3u);
  EXPECT_EQ(c.run_id, "r1, r2, r3");
  // Mean 2 passes; its interval 2 ± 2.484 spans the band [1.8, 2.2].
  EXPECT_EQ(c.rows[0].verdict, Verdict::kPass);
  ASSERT_TRUE(c.rows[0].interval);
  EXPECT_NEAR(c.rows[0].interval->high, 2 + 2.484138, 1e-6);
  EXPECT_EQ(c.rows[0].interval_verdict, IntervalVerdict::kAcross);
  EXPECT_EQ(c.rows[1].verdict, Verdict::kMiss);
  EXPECT_EQ(c.rows[1].interval_verdict, IntervalVerdict::kOutside);
  // 2 ± 4.302653 · 0.02 / √3 = 2 ± 0.0497: inside [1.8, 2.2].
  EXPECT_EQ(c.rows[2].verdict, Verdict::kPass);
  EXPECT_NEAR(c.rows[2].interval->low, 2 - 4.302653 * 0.02 / std::sqrt(3.0), 1e-6);
  EXPECT_EQ(c.rows[2].interval_verdict, IntervalVerdict::kInside);
  EXPECT_EQ(c.rows[3].verdict, Verdict::kNotApplicable);
  EXPECT_EQ(c.rows[3].absent_mode, "vio");
  EXPECT_FALSE(c.rows[3].interval);
  EXPECT_EQ(c.rows[4].verdict, Verdict::kNotFound);
  EXPECT_FALSE(c.rows[4].interval_verdict);
  EXPECT_EQ(c.counted(), 4u);  // n/a is not counted
  EXPECT_EQ(c.passed(), 2u);
  const std::string text = format_check(c);
  EXPECT_NE(text.find("paper check over 3 runs (r1, r2, r3;"), std::string::npos) << text;
  EXPECT_NE(text.find("2 [-0.4841, 4.484]"), std::string::npos) << text;
  EXPECT_NE(text.find("across"), std::string::npos) << text;
  EXPECT_NE(text.find("1 n/a (the run has no frames of their mode: vio)"), std::string::npos)
      << text;
  const nlohmann::json j = c.to_json();
  EXPECT_EQ(j["rows"][2]["interval_verdict"], "inside");
  EXPECT_EQ(j["rows"][0]["interval"]["n"], 3);
  EXPECT_EQ(j["rows"][3]["verdict"], "n/a");
  EXPECT_EQ(j["not_applicable"], 1);
}

TEST(CheckOverRuns, AFigureSomeRunLacksHasThatRunsVerdictAndNoInterval) {
  const std::vector<PaperTarget> targets = {
      target("kernel", "derived.kernels.marginalization.speedup", 2.0)};
  const CheckResult c =
      check_targets_over_runs(targets, {slam_run(2, 2.0), slam_run(2)}, {"a", "b"});
  EXPECT_EQ(c.rows[0].verdict, Verdict::kNotFound);
  EXPECT_FALSE(c.rows[0].interval);
  EXPECT_THROW(check_targets_over_runs(targets, {}, {}), std::invalid_argument);
  EXPECT_THROW(check_targets_over_runs(targets, {slam_run(2)}, {"a", "b"}), std::invalid_argument);
}

TEST(CheckOverRuns, OneRunIsThePointAndItsVerdictIsThePlainOne) {
  const std::vector<PaperTarget> targets = {
      target("spread", "system.comparison.all.e2e_speedup", 2.0)};
  const CheckResult one = check_targets_over_runs(targets, {slam_run(2.3)}, {"a"});
  const CheckResult plain = check_targets(targets, slam_run(2.3), "a");
  EXPECT_EQ(one.rows[0].verdict, plain.rows[0].verdict);
  EXPECT_DOUBLE_EQ(one.rows[0].error, plain.rows[0].error);
  EXPECT_FALSE(one.rows[0].interval->has_spread());
  EXPECT_EQ(one.rows[0].interval_verdict, IntervalVerdict::kOutside);
}

}  // namespace
}  // namespace edx::reports
