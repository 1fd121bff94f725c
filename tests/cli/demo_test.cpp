// End-to-end test of the demo (cli/demo.sh, what `./edx demo` runs) in its reduced size: the
// whole chain on small generated data and the real excerpts — mixed traces, simulation of both
// platforms into one results database, a sweep with its CSV, the HTML report with its plots, and
// the paper check table — and its handling of bad arguments.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/browser_check.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using edx::testing::built_binary;
using edx::testing::read_file;
using edx::testing::run_command;
using edx::testing::TempDir;
using ::testing::HasSubstr;

std::string demo_command(const fs::path& out) {
  return "bash " EDX_SOURCE_DIR "/cli/demo.sh --quick --jobs 2 --edx " + built_binary("edx") +
         " --shared " EDX_SHARED_DATA_DIR " --out " + out.string();
}

/// The reduced demo's run: its output folder, exit status, stdout and stderr. Under CTest the
/// fixture tests/cli/demo_fixture.sh ran it once for every test here (EDX_DEMO_RUN names its
/// folder); otherwise it runs once per process, into a temporary folder.
struct DemoRun {
  fs::path out;
  edx::testing::CommandResult result;
};

const DemoRun& demo_run() {
  static const TempDir scratch;
  static const DemoRun run = [] {
    const char* fixture = std::getenv("EDX_DEMO_RUN");
    if (fixture == nullptr || *fixture == '\0') {
      const fs::path out = scratch.path() / "demo";
      return DemoRun{out, run_command(demo_command(out))};
    }
    const fs::path dir(fixture);
    DemoRun r{dir / "out", {}};
    const std::string status = read_file(dir / "exit_code");
    r.result.exit_code = status.empty() ? -1 : std::stoi(status);
    r.result.out = read_file(dir / "stdout");
    r.result.err = read_file(dir / "stderr");
    return r;
  }();
  return run;
}

/// The single integer a query returns (-1 on any error).
long long query_integer(const fs::path& db, const std::string& sql) {
  sqlite3* handle = nullptr;
  long long value = -1;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(handle, sql.c_str(), -1, &statement, nullptr) == SQLITE_OK &&
        sqlite3_step(statement) == SQLITE_ROW) {
      value = sqlite3_column_int64(statement, 0);
    }
    sqlite3_finalize(statement);
  }
  sqlite3_close(handle);
  return value;
}

TEST(Demo, ReducedDemoRunsTheWholeChain) {
  const fs::path& out = demo_run().out;
  const edx::testing::CommandResult& result = demo_run().result;
  ASSERT_EQ(result.exit_code, 0) << result.err.substr(
      result.err.size() > 4000 ? result.err.size() - 4000 : 0);

  // Every step announced itself, in order, and the check table was printed.
  for (int step = 1; step <= 8; ++step) {
    EXPECT_THAT(result.err, HasSubstr("== [" + std::to_string(step) + "/8]"));
  }
  EXPECT_THAT(result.out, HasSubstr("targets within tolerance"));
  EXPECT_THAT(result.out, HasSubstr("e2e speedup overall"));
  // Over three seeds: each figure's mean and interval, each verdict's interval verdict.
  EXPECT_THAT(result.out, HasSubstr("paper check over 3 runs"));
  EXPECT_THAT(result.out, ::testing::ContainsRegex("(inside|across|outside)"));
  EXPECT_THAT(result.out, HasSubstr("speedup over single-core w/o ROS"));  // the baselines
  EXPECT_THAT(result.out, HasSubstr("ROS slowdown of the multi-core baseline"));
  // The characterization's targets are checked (its study given), not listed as not run.
  EXPECT_THAT(result.out, HasSubstr("char. least error indoor w/o map"));
  EXPECT_THAT(result.out, ::testing::Not(HasSubstr("not run")));
  EXPECT_THAT(result.out, HasSubstr((out / "report" / "index.html").string()));

  // Four traces: the two mixes and the two real excerpts.
  for (const char* name : {"car_mix", "drone_mix", "euroc_vio", "kitti_slam"}) {
    const fs::path trace = out / "traces" / (std::string(name) + ".db");
    ASSERT_TRUE(fs::exists(trace)) << trace;
    EXPECT_GT(query_integer(trace, "SELECT COUNT(*) FROM frames"), 10) << name;
  }
  // The mixes run all three backend modes.
  EXPECT_EQ(query_integer(out / "traces" / "car_mix.db",
                          "SELECT COUNT(DISTINCT backend_mode) FROM frames WHERE backend_mode IN "
                          "('registration', 'vio', 'slam')"),
            3);

  // Four simulated runs plus the sweep's points (7 block sizes x 2 policies), both platforms.
  const fs::path results = out / "results.db";
  EXPECT_GE(query_integer(results, "SELECT COUNT(*) FROM runs"), 4 + 1);
  EXPECT_EQ(query_integer(results,
                          "SELECT COUNT(*) FROM sweep_points WHERE sweep_id = "
                          "'gemm_block'"),
            14);
  EXPECT_GE(query_integer(results, "SELECT COUNT(*) FROM sweep_points WHERE pareto = 1"), 1);
  EXPECT_EQ(query_integer(results,
                          "SELECT COUNT(DISTINCT platform) FROM runs WHERE platform "
                          "IN ('edx_car', 'edx_drone')"),
            2);

  // The sweep's CSV: a header and one row per point.
  const std::string csv = read_file(out / "gemm_block.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 15) << csv.substr(0, 400);

  // The report: a page referencing plots that exist, and a frontend timeline.
  const std::string page = read_file(out / "report" / "index.html");
  EXPECT_THAT(page, HasSubstr("<img"));
  int svgs = 0;
  for (const auto& entry : fs::directory_iterator(out / "report")) {
    if (entry.path().extension() == ".svg") {
      ++svgs;
      EXPECT_GT(fs::file_size(entry.path()), 1000u) << entry.path();
    }
  }
  EXPECT_GE(svgs, 5);
  // Sections for the runs simulated by hand only (the two mixes, the two excerpts, the paper's
  // other baselines of configs/baselines/; each with its latency CDF); the sweep's other 13
  // points are rows of the Runs table that link to the sweep.
  int baselines = 0;
  for (const auto& entry :
       fs::directory_iterator(fs::path(EDX_SOURCE_DIR) / "configs" / "baselines")) {
    baselines += entry.path().extension() == ".yaml" ? 1 : 0;
  }
  EXPECT_GE(baselines, 3);
  int cdfs = 0;
  for (const auto& entry : fs::directory_iterator(out / "report")) {
    if (entry.path().filename().string().ends_with("_latency_cdf.svg")) ++cdfs;
  }
  EXPECT_EQ(cdfs, 4 + baselines);
  // The report's paper check compares Edx-Car with the single-core run of the same trace.
  EXPECT_EQ(query_integer(results,
                          "SELECT COUNT(*) FROM runs WHERE platform = 'car_single_core' AND "
                          "run_id NOT IN (SELECT run_id FROM seed_runs)"),
            1);
  std::size_t sweep_rows = 0;
  for (std::size_t at = page.find("(point of sweep"); at != std::string::npos;
       at = page.find("(point of sweep", at + 1)) {
    ++sweep_rows;
  }
  EXPECT_EQ(sweep_rows, 13u);
  // The summary first, then the paper check of each Edx-Car run (car mix, KITTI) with its plot.
  EXPECT_LT(page.find("id=\"summary\""), page.find("Paper check"));
  EXPECT_LT(page.find("Paper check"), page.find("<h2>Runs</h2>"));
  EXPECT_THAT(page, HasSubstr("edx_car × car_mix.db"));
  // The paper mix's check first; the KITTI run (SLAM frames only) lists the other modes' figures
  // as n/a; Table III beside Edx-Car's resources only, every run against its own device.
  const std::size_t kitti_check = page.find("Paper check: edx_car × kitti_slam.db");
  if (kitti_check != std::string::npos) {
    EXPECT_LT(page.find("Paper check: edx_car × car_mix.db"), kitti_check);
    EXPECT_THAT(page, HasSubstr("<span title=\"no vio frames here\">n/a</span>"));
  }
  EXPECT_THAT(page, HasSubstr("The design against its own device, ZU9CG"));
  EXPECT_THAT(page, HasSubstr("is compared only for Edx-Car runs"));
  EXPECT_THAT(page, HasSubstr("what-is-not-reachable-honestly-and-why"));
  EXPECT_THAT(page, HasSubstr("MODEL.md#miss-"));               // misses link their own explanation
  EXPECT_THAT(page, HasSubstr("alt=\"baseline comparison\""));  // the paper's other baselines
  // The paper's Sec. III figure redrawn with edx's characterization.
  EXPECT_THAT(page, HasSubstr("Algorithm characterization (paper Sec. III)"));
  EXPECT_THAT(page, HasSubstr("alt=\"characterization\""));
  EXPECT_TRUE(fs::exists(out / "characterization" / "characterization.json"));
  int comparison_charts = 0;
  for (const auto& entry : fs::directory_iterator(out / "report")) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("baselines") && name.ends_with(".svg")) ++comparison_charts;
  }
  EXPECT_GE(comparison_charts, 1);
  EXPECT_GT(fs::file_size(out / "car_system_timeline.json"), 1000u);
  // Every run the demo simulates keeps its whole-system timeline; the report links each,
  // written beside it.
  int timelines = 0;
  for (const auto& entry : fs::directory_iterator(out / "report")) {
    const std::string name = entry.path().filename().string();
    if (!name.ends_with("_timeline.json")) continue;
    ++timelines;
    EXPECT_GT(fs::file_size(entry.path()), 1000u) << name;
    EXPECT_THAT(page, HasSubstr("<a href=\"" + name + "\">")) << name;
  }
  EXPECT_EQ(timelines, cdfs);

  // Edx-Car and its compared baselines over the car mix's seeds 1-3: one group each, no
  // sections of their own; the group's paper check comes first, each figure with its interval
  // and interval verdict, and the summary gives each figure's interval.
  EXPECT_EQ(query_integer(results, "SELECT COUNT(*) FROM seed_runs"), 3 * (1 + baselines));
  const std::size_t seeds_check = page.find("Paper check: edx_car × frames");
  ASSERT_NE(seeds_check, std::string::npos);
  EXPECT_THAT(page.substr(seeds_check, 200), HasSubstr("(seeds 1, 2, 3)"));
  EXPECT_LT(seeds_check, page.find("Paper check: edx_car × car_mix.db"));
  EXPECT_THAT(page, HasSubstr("<th>interval</th>"));
  EXPECT_THAT(page, ::testing::ContainsRegex("<td>(inside|across|outside)</td>"));
  EXPECT_THAT(page.substr(0, page.find("Paper check")), HasSubstr("<small>["));
  // Each run section: its frames' critical-path attribution and the cause tables.
  int attributions = 0;
  for (const auto& entry : fs::directory_iterator(out / "report")) {
    if (entry.path().filename().string().ends_with("_attribution.svg")) ++attributions;
  }
  EXPECT_EQ(attributions, cdfs);
  EXPECT_THAT(page, HasSubstr("Causes, accelerated variant, isolated run"));
  EXPECT_THAT(page, HasSubstr("<td><b>bottleneck</b></td>"));
  // The sweep's front by bottleneck.
  EXPECT_THAT(page, HasSubstr("by the bottleneck of the point"));
}

// The demo's report in a real browser (headless Chromium at 1280 px): the page's test-only
// self-check (index.html?browser-check, docs/REPORTS.md) reports that every image loaded and
// that no element is wider than the viewport.
TEST(Demo, ReportRendersInABrowserAt1280Pixels) {
  if (!edx::testing::chromium_available()) {
    GTEST_SKIP() << "chromium not installed (./edx test installs it): browser check skipped";
  }
  ASSERT_EQ(demo_run().result.exit_code, 0) << demo_run().result.err;
  const TempDir dir;
  const auto check_or = edx::testing::browser_check(demo_run().out / "report" / "index.html",
                                                    dir.path() / "chromium");
  ASSERT_TRUE(check_or);
  const nlohmann::json& check = *check_or;
  EXPECT_GE(check.at("images").get<int>(), 5) << check.dump();
  EXPECT_TRUE(check.at("broken").empty()) << check.dump();
  EXPECT_TRUE(check.at("wide").empty()) << check.dump();
  EXPECT_LE(check.at("scroll_width").get<int>(), check.at("viewport").get<int>()) << check.dump();
}

TEST(Demo, BadArgumentsAreOneLineErrorsWithExitTwo) {
  const auto unknown = run_command("bash " EDX_SOURCE_DIR "/cli/demo.sh --edx " +
                                   built_binary("edx") + " --frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_THAT(unknown.err, HasSubstr("--frobnicate"));
  EXPECT_EQ(std::count(unknown.err.begin(), unknown.err.end(), '\n'), 1);

  const auto no_binary = run_command("bash " EDX_SOURCE_DIR "/cli/demo.sh --edx /no/such/edx");
  EXPECT_EQ(no_binary.exit_code, 2);
  EXPECT_THAT(no_binary.err, HasSubstr("/no/such/edx"));

  const auto bad_jobs = run_command("bash " EDX_SOURCE_DIR "/cli/demo.sh --edx " +
                                    built_binary("edx") + " --jobs zero");
  EXPECT_EQ(bad_jobs.exit_code, 2);
  EXPECT_THAT(bad_jobs.err, HasSubstr("--jobs"));
}

}  // namespace
