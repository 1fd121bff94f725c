// Accuracy in the design loop (docs/SWEEPS.md "Accuracy"): the ATE metrics of a point's trace as
// objectives and constraints, a constraint relative to a reference workload point (traced when it
// is no grid point), an undefined metric making a point infeasible, the spec's errors, and a
// search over workload and platform parameters together.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <set>

#include "arch/sweep/sweep.hpp"
#include "arch/sweep/workload.hpp"
#include "tests/arch/sweep/sweep_fixture.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

/// A stand-in for the pipeline: workload {features: N, window: W} traces one segment of 4 VIO
/// frames whose estimates are off by +-N/1000 m in z, then 4 SLAM frames off by +-W/100 m (when
/// W > 0; W = 0: SLAM runs without an estimate). Known ATEs: vio N/1000, slam W/100.
struct AccuracyTracer {
  std::atomic<int> traced{0};
  WorkloadTracer tracer() {
    return {[](const nlohmann::json& w) {
              nlohmann::json resolved = {{"features", 100}, {"window", 10}};
              for (const auto& [key, value] : w.items()) {
                if (key != "features" && key != "window") throw InputError({}, key, "unknown");
                const int n = std::stoi(value.get<std::string>());
                if (n < 0) throw InputError::expected(key, "at least 0", std::to_string(n));
                resolved[key] = n;
              }
              return resolved;
            },
            [this](const nlohmann::json& resolved, const std::filesystem::path& out,
                   const std::filesystem::path&) {
              ++traced;
              trace::TraceMeta meta = sweep_trace_meta();
              trace::TraceWriter writer(out, meta);
              const double vio = resolved.at("features").get<int>() / 1000.0;
              const int window = resolved.at("window").get<int>();
              for (int i = 0; i < 8; ++i) {
                trace::FrameTrace f = sweep_frame(i, 1000 + 100 * i);
                f.frame.mode = i < 4 ? trace::BackendMode::Vio : trace::BackendMode::Slam;
                const double x = 0.1 * i, y = 0.02 * i * i;
                const double d = (i % 2 ? -1 : 1) * (i < 4 ? vio : window / 100.0);
                f.frame.ground_truth_pose = trace::PoseArray{x, y, 0, 1, 0, 0, 0};
                if (i < 4 || window > 0) {
                  f.frame.estimated_pose = trace::PoseArray{x + 1, y, d, 1, 0, 0, 0};
                }
                writer.append(f);
              }
              writer.finish();
            },
            "v1"};
  }
};

struct AccuracySweep : ::testing::Test {
  edx::testing::TempDir dir;
  AccuracyTracer fake;
  void SetUp() override {
    std::ofstream(dir.path() / "base.yaml")
        << "name: w\nbackend: {clock_mhz: 100, spm_bytes: 67108864, units: {gemm: {block: 2}}}\n"
           "scheduler: {policy: always, training_fraction: 0}\n";
  }
  SweepSpec spec(const std::string& rest) const {
    return SweepSpec::parse("base: base.yaml\nworkload: {window: 10}\n" + rest, "a.yaml",
                            dir.path());
  }
  SweepOptions options() {
    SweepOptions o;
    o.db = dir.path() / "r.db";
    o.jobs = 2;
    o.tracer = fake.tracer();
    return o;
  }
  /// The error of parsing (and resolving) a spec, "no error" when there is none.
  std::string error(const std::string& rest) {
    try {
      const SweepSpec s = spec(rest);
      SweepOptions o = options();
      o.db = dir.path() / "error.db";
      run_sweep(s, o);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }
};

TEST_F(AccuracySweep, AteMetricsAreTheTracesKnownErrorsAndARelativeConstraintBoundsThem) {
  // Features 100 is the reference: 105 is 5 % worse (feasible within 10 %), 150 50 % (not).
  const SweepSpec s = spec(
      "parameters:\n  workload.features: {values: [100, 105, 150]}\n"
      "  backend.units.gemm.block: {values: [1, 4]}\n"
      "objectives: [{minimize: e2e_latency_mean}, {minimize: ate_rmse_vio}]\n"
      "constraints:\n"
      "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: {workload.features: 100}}\n"
      "  - {metric: ate_rmse_slam, max: 0.2}\n"
      "  - {metric: ate_rmse, max: 1}\n");
  ASSERT_TRUE(s.needs_accuracy());
  const SweepOutcome out = run_sweep(s, options());
  ASSERT_EQ(out.points.size(), 6u);
  EXPECT_EQ(fake.traced, 3);  // the reference is a grid point: traced once
  for (const SweepPointResult& p : out.points) {
    const double features = std::stod(p.parameters["workload.features"].get<std::string>());
    EXPECT_NEAR(p.metrics.at("ate_rmse_vio").get<double>(), features / 1000, 1e-12) << p.index;
    EXPECT_NEAR(p.metrics.at("ate_rmse_vio_reference").get<double>(), 0.1, 1e-12);
    EXPECT_NEAR(p.metrics.at("ate_rmse_slam").get<double>(), 0.1, 1e-12);
    // All: both modes pooled, 4 pairs each.
    EXPECT_NEAR(p.metrics.at("ate_rmse").get<double>(),
                std::sqrt((4 * std::pow(features / 1000, 2) + 4 * 0.01) / 8), 1e-12);
    ASSERT_EQ(p.constraints.size(), 3u);
    EXPECT_NEAR(p.constraints[0], features / 100, 1e-12);  // the ratio to the reference
    EXPECT_EQ(p.feasible, features < 150) << p.index;
  }
  EXPECT_EQ(s.to_json().at("constraints")[0].at("reference"),
            (nlohmann::json{{"workload.features", "100"}}));
}

TEST_F(AccuracySweep, AReferenceOutsideTheGridIsTracedOnceAndShared) {
  const SweepSpec s = spec(
      "parameters:\n  workload.features: {values: [105, 150]}\n"
      "  workload.window: {values: [10, 20]}\n"
      "objectives: [{minimize: ate_rmse_vio}]\n"
      "constraints:\n"
      "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: {workload.features: 100}}\n");
  const SweepOutcome out = run_sweep(s, options());
  ASSERT_EQ(out.points.size(), 4u);
  // 4 grid workload points and the references (features 100) at window 10 and 20.
  EXPECT_EQ(fake.traced, 6);
  EXPECT_EQ(out.traced, 6u);
  for (const SweepPointResult& p : out.points) {
    EXPECT_EQ(p.feasible, p.parameters["workload.features"] == "105") << p.index;
  }
  // Again: every trace from the store, every point from the database.
  const SweepOutcome again = run_sweep(s, options());
  EXPECT_EQ(fake.traced, 6);
  EXPECT_EQ(again.skipped, 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(again.points[i].feasible, out.points[i].feasible);
}

TEST_F(AccuracySweep, AnUndefinedAteMakesThePointInfeasible) {
  // Window 0: SLAM runs without an estimate, so ate_rmse_slam is undefined (null) there;
  // registration never runs at all.
  const SweepSpec s = spec(
      "parameters:\n  workload.window: {values: [0, 10]}\n"
      "objectives: [{minimize: ate_rmse_slam}, {minimize: ate_rmse_registration}]\n");
  const SweepOutcome out = run_sweep(s, options());
  ASSERT_EQ(out.points.size(), 2u);
  EXPECT_TRUE(out.points[0].metrics.at("ate_rmse_slam").is_null());
  EXPECT_NEAR(out.points[1].metrics.at("ate_rmse_slam").get<double>(), 0.1, 1e-12);
  for (const SweepPointResult& p : out.points) {
    EXPECT_TRUE(p.metrics.at("ate_rmse_registration").is_null());
    EXPECT_FALSE(p.feasible);
  }
  EXPECT_TRUE(out.front.empty());
  EXPECT_THAT(format_sweep(s, out), HasSubstr("pareto     0 of 0 feasible points"));
  // CSV: an undefined metric is an empty field.
  EXPECT_EQ(export_csv(dir.path() / "r.db", "", "a", dir.path() / "a.csv"), 2u);
}

TEST_F(AccuracySweep, BadConstraintsAreOneLineErrorsAtTheirLineAndKey) {
  const std::string params =
      "parameters:\n  workload.features: {values: [100, 150]}\n"
      "objectives: [{minimize: ate_rmse_vio}]\nconstraints:\n";
  EXPECT_EQ(error(params + "  - {metric: ate_rmse_vio, max_relative: 0.1}\n"),
            "a.yaml:7: constraints[0].max_relative: needs reference: {workload.KEY: VALUE, ...}, "
            "the workload point it is relative to");
  EXPECT_EQ(error(params + "  - {metric: ate_rmse_vio, reference: {workload.features: 1}}\n"),
            "a.yaml:7: constraints[0].reference: needs max_relative: X (a fraction)");
  EXPECT_EQ(error(params + "  - {metric: ate_rmse_vio, max: 1, max_relative: 0.1, "
                           "reference: {workload.features: 1}}\n"),
            "a.yaml:7: constraints[0].max: a relative constraint takes max_relative and "
            "reference, not min or max");
  EXPECT_EQ(error(params + "  - {metric: e2e_latency_mean, max_relative: 0.1, "
                           "reference: {workload.features: 1}}\n"),
            "a.yaml:7: constraints[0].metric: expected an accuracy metric (ate_rmse, "
            "ate_rmse_vio, ate_rmse_slam, ate_rmse_registration) with max_relative, got "
            "'e2e_latency_mean'");
  EXPECT_EQ(
      error(params + "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: {features: 1}}\n"),
      "a.yaml:7: constraints[0].reference.features: expected a workload.* key (the "
      "reference is a workload point)");
  EXPECT_EQ(error(params + "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: []}\n"),
            "a.yaml:7: constraints[0].reference: expected a map of workload.* keys to values");
  EXPECT_THAT(error(params + "  - {metric: ate_rmse_vio, max_relative: -1, "
                             "reference: {workload.features: 1}}\n"),
              HasSubstr("a.yaml:7: constraints[0].max_relative: expected"));
  EXPECT_EQ(error(params + "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: "
                           "{workload.features: 1}, maximum: 2}\n"),
            "a.yaml:7: constraints[0].maximum: unknown key (expected one of: metric, min, max, "
            "max_relative, reference)");
  EXPECT_EQ(
      error(params +
            "  - {metric: ate_rmse_vio, max_relative: 0.1, reference: {workload.features: 1}}\n"
            "  - {metric: ate_rmse_vio, max_relative: 0.2, reference: {workload.features: 2}}\n"),
      "a.yaml:8: constraints[1].metric: a second relative constraint on 'ate_rmse_vio' (one "
      "per metric)");
  // A reference value the workload refuses: at its line, keyed as the spec writes it.
  EXPECT_EQ(error(params + "  - metric: ate_rmse_vio\n    max_relative: 0.1\n"
                           "    reference: {workload.features: -5}\n"),
            "a.yaml:9: constraints[0].reference.workload.features: expected at least 0, got '-5'");
  // A relative constraint needs a workload sweep.
  std::ofstream(dir.path() / "t.db") << "";
  EXPECT_THAT(
      [&] {
        try {
          SweepSpec::parse(
              "base: base.yaml\ntrace: t.db\nparameters:\n"
              "  backend.units.gemm.block: {values: [1]}\n"
              "objectives: [{minimize: ate_rmse}]\nconstraints:\n"
              "  - {metric: ate_rmse, max_relative: 0.1, reference: "
              "{workload.features: 1}}\n",
              "a.yaml", dir.path());
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
        return std::string("no error");
      }(),
      HasSubstr("a.yaml:7: constraints[0].reference: needs a workload: section"));
  EXPECT_EQ(fake.traced, 0);
}

TEST_F(AccuracySweep, ASearchVariesWorkloadAndPlatformGenesAndFindsTheGridsFront) {
  const std::string rest =
      "parameters:\n  workload.features: {values: [100, 120, 140, 160]}\n"
      "  workload.window: {values: [10, 20]}\n"
      "  backend.units.gemm.block: {values: [1, 2, 4, 8]}\n"
      "objectives: [{minimize: e2e_latency_mean}, {minimize: ate_rmse}]\n"
      "constraints:\n"
      "  - {metric: ate_rmse_slam, max_relative: 0.5, reference: {workload.window: 10}}\n";
  const SweepSpec grid = spec("name: grid\n" + rest);
  const SweepSpec search =
      spec("name: search\n" + rest + "sampling: {nsga2: {generations: 8, population: 8}}\n");
  const SweepOutcome g = run_sweep(grid, options());
  const SweepOutcome n = run_sweep(search, options());
  EXPECT_EQ(fake.traced, 8);  // every workload point once, shared by both sweeps (one store)
  std::set<nlohmann::json> grid_front, search_front;
  for (std::size_t i : g.front) grid_front.insert(g.points[i].metrics);
  for (std::size_t i : n.front) search_front.insert(n.points[i].metrics);
  EXPECT_EQ(search_front, grid_front);
  for (const SweepPointResult& p : n.points) {
    EXPECT_EQ(p.feasible, p.parameters["workload.window"] == "10") << p.index;  // 20: 2x SLAM ATE
  }
  ASSERT_FALSE(n.generations.empty());
  EXPECT_GT(n.generations.back().hypervolume, 0);
}

}  // namespace
}  // namespace edx::arch
