// The NSGA-II design search (arch/sweep/search, pagmo2): the issue-19 bar on a 5 120-point car
// space, determinism, resume and the spec's checks.
#include "arch/sweep/search.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "arch/sweep/sweep.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

const std::string kSource = EDX_SOURCE_DIR;

/// Six Edx-Car parameters (frontend lanes, DR rate, gemm block, decomposition lanes, backend
/// clock, link bandwidth): 4 x 4 x 4 x 4 x 5 x 4 = 5 120 designs.
std::string car_space(const std::string& sampling, const std::string& name) {
  return "name: " + name + "\nbase: " + kSource +
         "/configs/edx_car.yaml\nparameters:\n"
         "  frontend.fe_pixels_per_cycle: {values: [1, 2, 4, 8]}\n"
         "  frontend.units.DR.pixels_per_cycle: {values: [0.25, 0.5, 1, 2]}\n"
         "  backend.units.gemm.block: {values: [2, 4, 8, 16]}\n"
         "  backend.units.decomposition.block: {values: [1, 2, 4, 8]}\n"
         "  backend.clock_mhz: {values: [100, 150, 200, 250, 300]}\n"
         "  link.bandwidth_gb_per_s: {values: [1, 2, 4, 7.9]}\n"
         "sampling: " +
         sampling +
         "\nobjectives: [{minimize: e2e_latency_mean}, {minimize: lut}]\n"
         "constraints: [{metric: resources, max: 1.0}]\n";
}

/// The first 80 frames of the golden mix (all in memory: the sweeps below share them).
struct SmallTrace {
  std::vector<trace::FrameTrace> frames;
  trace::TraceMeta meta;
  SmallTrace() {
    const trace::TraceReader reader(kSource + "/tests/data/golden/golden_mix.db");
    frames = reader.read_all();
    frames.resize(80);
    meta = reader.meta();
  }
};

const SmallTrace& small_trace() {
  static const SmallTrace trace;
  return trace;
}

SweepOutcome run(const SweepSpec& spec, const std::filesystem::path& db, std::size_t limit = 0) {
  SweepOptions options;
  options.db = db;
  options.jobs = 2;
  options.limit = limit;
  return run_sweep(spec, options, small_trace().frames, small_trace().meta, "golden_mix[0:80]");
}

/// Feasible designs' objectives in minimization form.
std::vector<std::vector<double>> feasible_rows(const SweepSpec& spec, const SweepOutcome& o) {
  std::vector<std::vector<double>> rows;
  for (const SweepPointResult& p : o.points) {
    if (p.feasible) rows.push_back(minimization_form(spec, p.objectives));
  }
  return rows;
}

// Issue 19's bar: with at most 10 % of the grid's evaluations, NSGA-II finds a front whose
// hypervolume is at least 95 % of the whole grid's, both against the grid's reference point.
TEST(Search, Nsga2ReachesTheGridsFrontWithATenthOfItsEvaluations) {
  const testing::TempDir dir;
  const SweepSpec grid = SweepSpec::parse(car_space("grid", "grid"), "grid.yaml", dir.path());
  const SweepSpec search =
      SweepSpec::parse(car_space("{nsga2: {generations: 15, population: 32, seed: 1}}", "search"),
                       "search.yaml", dir.path());
  ASSERT_EQ(grid_size(grid), 5120);
  const SweepOutcome all = run(grid, dir.path() / "grid.db");
  const SweepOutcome found = run(search, dir.path() / "search.db");
  ASSERT_TRUE(found.complete);
  EXPECT_LE(found.points.size(), 512u);  // distinct designs simulated
  const auto grid_rows = feasible_rows(grid, all);
  ASSERT_GT(grid_rows.size(), 100u);
  std::vector<double> reference(2, -std::numeric_limits<double>::infinity());
  for (const auto& row : grid_rows) {
    for (std::size_t i = 0; i < 2; ++i) reference[i] = std::max(reference[i], row[i] * 1.01);
  }
  const double grid_hv = front_hypervolume(grid_rows, reference);
  const double search_hv = front_hypervolume(feasible_rows(search, found), reference);
  ASSERT_GT(grid_hv, 0);
  EXPECT_GE(search_hv / grid_hv, 0.95) << "search " << search_hv << ", grid " << grid_hv;
  // The convergence table: the initial population and 15 generations, the hypervolume of the
  // front found so far never falling, the evaluations counted once per design.
  ASSERT_EQ(found.generations.size(), 16u);
  EXPECT_EQ(found.generations.front().evaluations, 32u);
  EXPECT_EQ(found.generations.back().evaluations, found.points.size());
  for (std::size_t g = 1; g < found.generations.size(); ++g) {
    EXPECT_GE(found.generations[g].hypervolume, found.generations[g - 1].hypervolume);
  }
}

TEST(Search, SameSeedSameDesignsAndAResumedSearchEndsTheSame) {
  const testing::TempDir dir;
  const SweepSpec spec = SweepSpec::parse(
      car_space("{nsga2: {generations: 4, population: 16, seed: 7}}", "s"), "s.yaml", dir.path());
  const SweepOutcome first = run(spec, dir.path() / "a.db");
  const SweepOutcome second = run(spec, dir.path() / "b.db");
  ASSERT_EQ(first.points.size(), second.points.size());
  for (std::size_t i = 0; i < first.points.size(); ++i) {
    EXPECT_EQ(first.points[i].index, second.points[i].index);
    EXPECT_EQ(first.points[i].objectives, second.points[i].objectives);
  }
  ASSERT_EQ(first.generations.size(), 5u);
  for (std::size_t g = 0; g < first.generations.size(); ++g) {
    EXPECT_EQ(first.generations[g].hypervolume, second.generations[g].hypervolume);
  }
  // Stopped by the limit, then resumed: the stored designs are read back, not simulated again,
  // and the search ends where the uninterrupted one did.
  const SweepOutcome stopped = run(spec, dir.path() / "c.db", 20);
  EXPECT_FALSE(stopped.complete);
  EXPECT_TRUE(stopped.generations.empty());
  const SweepOutcome resumed = run(spec, dir.path() / "c.db");
  EXPECT_TRUE(resumed.complete);
  EXPECT_EQ(resumed.skipped, 20u);
  EXPECT_EQ(resumed.computed + resumed.skipped, first.points.size());
  ASSERT_EQ(resumed.front.size(), first.front.size());
  for (std::size_t i = 0; i < first.front.size(); ++i) {
    EXPECT_EQ(resumed.points[resumed.front[i]].index, first.points[first.front[i]].index);
  }
}

TEST(Search, CategoricalAndLogRangeParametersAreGenesAFixedOneIsNot) {
  const testing::TempDir dir;
  const SweepSpec spec = SweepSpec::parse(
      "name: mixed\nbase: " + kSource +
          "/configs/edx_car.yaml\nparameters:\n"
          "  scheduler.policy: {values: [regression, always, never]}\n"
          "  link.bandwidth_gb_per_s: {log_range: {from: 1.2, to: 7.9, points: 4}}\n"
          "  backend.units.gemm.block: {values: [2, 4]}\n"
          "  backend.units.decomposition.block: {values: [1]}\n"  // fixed: no gene
          "sampling: {nsga2: {generations: 2, population: 8, seed: 3}}\n"
          "objectives: [{minimize: e2e_latency_mean}, {minimize: dsp}]\n",
      "mixed.yaml", dir.path());
  const SweepOutcome o = run(spec, dir.path() / "m.db");
  ASSERT_TRUE(o.complete);
  EXPECT_LE(o.points.size(), 24u);  // 3 x 4 x 2 designs
  std::set<std::string> policies;
  for (const SweepPointResult& p : o.points) {
    policies.insert(p.parameters["scheduler.policy"].get<std::string>());
    // The grid index is the design's point: its parameters are the grid's at that index.
    EXPECT_EQ(p.parameters, SweepPoints(spec).at(p.index).parameters(spec));
  }
  EXPECT_GE(policies.size(), 2u);
  EXPECT_FALSE(o.front.empty());
}

TEST(Search, SpecChecksNameTheKey) {
  const testing::TempDir dir;
  const auto error_of = [&](const std::string& sampling) {
    try {
      SweepSpec::parse(car_space(sampling, "s"), "s.yaml", dir.path());
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of("{nsga2: {generations: 5, population: 10}}"),
              HasSubstr("s.yaml:10: sampling.nsga2.population: expected a multiple of 4 from 8 to "
                        "10000"));
  EXPECT_THAT(error_of("{nsga2: {generations: 0, population: 8}}"),
              HasSubstr("sampling.nsga2.generations: expected an integer from 1 to 10000"));
  EXPECT_THAT(error_of("{nsga2: {generations: 5, population: 8, seed: -1}}"),
              HasSubstr("sampling.nsga2.seed: expected an integer from 0 to 2^32 - 1"));
  EXPECT_THAT(error_of("{nsga2: {generations: 5000, population: 400}}"),
              HasSubstr("sampling.nsga2: population x (generations + 1) = 2e+06 "
                        "evaluations (more than 10^6)"));
  EXPECT_THAT(error_of("{nsga2: {generations: 5, population: 8, elitism: 2}}"),
              HasSubstr("elitism"));
}

TEST(Search, NothingToSearchIsOneLineAndLeavesNoDatabase) {
  const testing::TempDir dir;
  const SweepSpec spec = SweepSpec::parse(
      "name: fixed\nbase: " + kSource +
          "/configs/edx_car.yaml\nparameters:\n  backend.units.gemm.block: {values: [4]}\n"
          "sampling: {nsga2: {generations: 2, population: 8}}\n"
          "objectives: [{minimize: e2e_latency_mean}, {minimize: dsp}]\n",
      "fixed.yaml", dir.path());
  try {
    run(spec, dir.path() / "f.db");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "fixed.yaml: sampling.nsga2: every parameter has one value: nothing to search (use "
              "grid)");
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "f.db"));
}

TEST(Search, FrontHypervolumeByHand) {
  // Two points (1, 3) and (2, 1) against (4, 4): 3x1 + 2x2 = 7 (the union of two rectangles,
  // 3 + 6 - 2); a dominated point and one outside the reference change nothing.
  EXPECT_DOUBLE_EQ(front_hypervolume({{1, 3}, {2, 1}}, {4, 4}), 7.0);
  EXPECT_DOUBLE_EQ(front_hypervolume({{1, 3}, {2, 1}, {3, 3}, {5, 0}}, {4, 4}), 7.0);
  EXPECT_DOUBLE_EQ(front_hypervolume({}, {4, 4}), 0.0);
}

}  // namespace
}  // namespace edx::arch
