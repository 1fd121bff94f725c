// The joint search of accuracy, latency and resources end to end with the real pipeline
// (docs/SWEEPS.md "Accuracy"): NSGA-II over two MSCKF windows (the paper mix, 160 frames at
// 320x240, traced as the search asks) and two platform parameters, ATE RMSE an objective and
// VIO's ATE within 10 % of the 30-clone window's; stopped by --limit and resumed to the front of
// an uninterrupted run; `edx report` draws the accuracy-latency-resources front, and the page
// renders in headless Chromium (when installed).
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/support/browser_check.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using edx::testing::run_command;
using ::testing::HasSubstr;

const std::string kEdx = edx::testing::built_binary("edx");

/// The front of `edx sweep --json` as a set of point indices.
std::set<std::size_t> front_of(const std::string& json) {
  const nlohmann::json result = nlohmann::json::parse(json);  // alive through the loop
  std::set<std::size_t> front;
  for (const auto& i : result.at("pareto_front")) front.insert(i.get<std::size_t>());
  return front;
}

TEST(AccuracySearch, ResumesToTheFrontOfAnUninterruptedRunAndTheReportDrawsIt) {
  const edx::testing::TempDir dir;
  const fs::path spec = dir.path() / "acc.yaml";
  std::ofstream(spec) << "name: acc\nbase: " EDX_SOURCE_DIR
                         "/configs/edx_car.yaml\n"
                         "workload: {mix: paper, frames: 160, resolution: 320x240, features: 150}\n"
                         "parameters:\n"
                         "  workload.msckf_window: {values: [10, 30]}\n"
                         "  frontend.fe_pixels_per_cycle: {values: [1, 2, 4]}\n"
                         "  backend.units.gemm.block: {values: [2, 4, 8]}\n"
                         "sampling: {nsga2: {generations: 2, population: 8, seed: 3}}\n"
                         "objectives: [{minimize: e2e_latency_mean}, {minimize: lut}, "
                         "{minimize: ate_rmse}]\n"
                         "constraints:\n"
                         "  - {metric: resources, max: 1.0}\n"
                         "  - {metric: ate_rmse_vio, max_relative: 0.1, "
                         "reference: {workload.msckf_window: 30}}\n";
  const fs::path store = dir.path() / "store";
  const std::string run = fmt::format("{} sweep {} --trace-store {} -j 2 --json --db ", kEdx,
                                      spec.string(), store.string());
  // Stopped after 4 simulated designs, then resumed.
  auto first = run_command(run + (dir.path() / "a.db").string() + " --limit 4");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_FALSE(nlohmann::json::parse(first.out).at("complete").get<bool>());
  auto resumed = run_command(run + (dir.path() / "a.db").string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const nlohmann::json r = nlohmann::json::parse(resumed.out);
  EXPECT_TRUE(r.at("complete").get<bool>());
  EXPECT_EQ(r.at("traced").get<int>(), 0);  // both workload points were traced by the first run
  EXPECT_GE(r.at("skipped").get<int>(), 4);
  // The same search uninterrupted, on the same traces: the same front.
  auto whole = run_command(run + (dir.path() / "b.db").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_EQ(front_of(resumed.out), front_of(whole.out));
  ASSERT_FALSE(front_of(whole.out).empty()) << whole.out.substr(0, 2000);
  for (const auto& p : r.at("points")) {
    ASSERT_TRUE(p.at("metrics").at("ate_rmse").is_number()) << p.dump();
    // The reference's VIO error, and the window-30 points are their own reference.
    if (p.at("parameters").at("workload.msckf_window") == "30") {
      EXPECT_EQ(p.at("metrics").at("ate_rmse_vio"), p.at("metrics").at("ate_rmse_vio_reference"));
    }
  }

  const fs::path report = dir.path() / "report";
  const auto rep = run_command(
      fmt::format("{} report {} --out {}", kEdx, (dir.path() / "a.db").string(), report.string()));
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  const std::string page = edx::testing::read_file(report / "index.html");
  EXPECT_THAT(page, HasSubstr("Accuracy, latency and resources"));
  EXPECT_THAT(page, HasSubstr("sweep1_accuracy.svg"));
  EXPECT_GT(fs::file_size(report / "sweep1_accuracy.svg"), 1000u);

  if (!edx::testing::chromium_available()) {
    GTEST_SKIP() << "chromium not installed (./edx test installs it): browser check skipped";
  }
  const auto check_or = edx::testing::browser_check(report / "index.html", dir.path() / "chromium");
  ASSERT_TRUE(check_or);
  const nlohmann::json& check = *check_or;
  EXPECT_GE(check.at("images").get<int>(), 3) << check.dump();
  EXPECT_TRUE(check.at("broken").empty()) << check.dump();
  EXPECT_TRUE(check.at("wide").empty()) << check.dump();
}

}  // namespace
