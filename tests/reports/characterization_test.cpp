// The paper's algorithm characterization (workloads/modes/characterization.hpp,
// reports/characterization.hpp; issue 42): the cells and their plans, the paper's statements as
// read from the targets file, and the whole study end to end on small worlds: every run traced
// with its backend on every measured frame, its accuracy and frame rate, the orderings, and the
// runs reused when traced already.
#include "reports/characterization.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <numeric>

#include "arch/platform/platform.hpp"
#include "common/resources.hpp"
#include "reports/paper_check.hpp"
#include "tests/support/temp_dir.hpp"
#include "workloads/modes/characterization.hpp"
#include "workloads/trace/reader.hpp"

namespace edx::reports {
namespace {

using modes::CharacterizationCell;
using synthetic::Scenario;
using ::testing::HasSubstr;
using trace::BackendMode;

TEST(Characterization, EveryScenarioHasItsApplicableBackends) {
  const std::vector<CharacterizationCell> cells = modes::characterization_cells();
  ASSERT_EQ(cells.size(), 10u);  // vio and slam everywhere, registration where a map exists
  int registration = 0;
  for (const CharacterizationCell& c : cells) {
    if (c.backend == BackendMode::Registration) {
      ++registration;
      EXPECT_TRUE(synthetic::has_map_run(c.scenario));
    }
  }
  EXPECT_EQ(registration, 2);
  // A known scenario: its mapping run (SLAM) first, then the measured run with the backend.
  const modes::MixPlan known = modes::characterization_plan(
      {Scenario::kIndoorKnown, BackendMode::Registration}, 50, {320, 240}, 1001);
  ASSERT_EQ(known.segments.size(), 2u);
  EXPECT_EQ(known.segments[0].run, "map");
  EXPECT_EQ(known.segments[0].mode, BackendMode::Slam);
  EXPECT_EQ(known.segments[1].run, "loc");
  EXPECT_EQ(known.segments[1].mode, BackendMode::Registration);
  EXPECT_EQ(known.segments[0].world, known.segments[1].world);
  EXPECT_EQ(known.segments[1].scenario, trace::Scenario::IndoorKnown);
  const modes::MixPlan street = modes::characterization_plan(
      {Scenario::kOutdoorUnknown, BackendMode::Vio}, 50, {320, 240}, 1001);
  ASSERT_EQ(street.segments.size(), 1u);
  EXPECT_EQ(street.segments[0].mode, BackendMode::Vio);
  EXPECT_EQ(street.segments[0].scenario, trace::Scenario::OutdoorUnknown);

  modes::CharacterizationOptions bad;
  bad.frames = 4;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(Characterization, ThePapersStatementsLoadFromTheTargetsFile) {
  const PaperCharacterization paper = PaperCharacterization::load(default_targets_path());
  EXPECT_EQ(paper.points.size(), 8u);
  ASSERT_EQ(paper.scenarios.size(), 4u);
  EXPECT_EQ(paper.scenarios[0].least_error, "slam");
  EXPECT_EQ(paper.scenarios[1].fastest, "vio");
  const edx::testing::TempDir dir;
  const std::filesystem::path file = dir.path() / "t.yaml";
  std::ofstream(file) << "targets: [{name: a, metric: b, paper: 1}]\ncharacterization:\n"
                         "  points:\n    - {scenario: moon, backend: vio}\n  scenarios: []\n";
  try {
    PaperCharacterization::load(file);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("t.yaml:4: characterization.points[].scenario: expected "
                                    "indoor_unknown, indoor_known, outdoor_unknown or "
                                    "outdoor_known, got 'moon'"));
  }
}

TEST(Characterization, EndToEndOnSmallWorlds) {
  const edx::testing::TempDir dir;
  modes::CharacterizationOptions options;
  options.seeds = 1;
  options.frames = 32;
  options.resolution = {376, 240};
  options.data_dir = dir.path() / "data";
  options.trace_dir = dir.path() / "traces";
  const std::vector<modes::CharacterizationRun> runs = modes::run_characterization(options);
  ASSERT_EQ(runs.size(), 10u);
  for (const modes::CharacterizationRun& run : runs) {
    const std::string name = fmt::format("{} {}", synthetic::to_string(run.cell.scenario),
                                         trace::to_string(run.cell.backend));
    EXPECT_EQ(run.seed, modes::kCharacterizationFirstSeed) << name;
    EXPECT_EQ(run.frames, 32u) << name;
    EXPECT_EQ(run.first_frame_id, synthetic::has_map_run(run.cell.scenario) ? 32 : 0) << name;
    // Every measured frame ran the run's backend, whatever the mode switch would have chosen.
    const trace::TraceReader reader(run.trace.string());
    for (const trace::FrameTrace& f : reader.read_all()) {
      if (f.frame.frame_id >= run.first_frame_id) {
        EXPECT_EQ(f.frame.mode, run.cell.backend) << name;
      }
    }
    ASSERT_TRUE(run.ate_rmse_m) << name;
    EXPECT_GT(*run.ate_rmse_m, 0.0) << name;
    EXPECT_LT(*run.ate_rmse_m, 1.0) << name;
  }
  const arch::Platform platform =
      arch::Platform::load(common::find_resource("configs/edx_car.yaml").string());
  const PaperCharacterization paper = PaperCharacterization::load(default_targets_path());
  const CharacterizationStudy study = study_characterization(runs, platform, paper);
  ASSERT_EQ(study.points.size(), 10u);
  ASSERT_EQ(study.scenarios.size(), 4u);
  for (const CharacterizationStudy::ScenarioResult& s : study.scenarios) {
    // The least error and the fastest are the points' argmin and argmax.
    double least = 1e9, fastest = 0;
    std::string least_name, fastest_name;
    for (const CharacterizationPoint& p : study.points) {
      if (p.scenario != s.scenario) continue;
      EXPECT_GT(p.fps_mean, 1.0) << p.scenario << " " << p.backend;
      if (p.ate_mean_m < least) least = p.ate_mean_m, least_name = p.backend;
      if (p.fps_mean > fastest) fastest = p.fps_mean, fastest_name = p.backend;
    }
    EXPECT_EQ(s.least_error, least_name) << s.scenario;
    EXPECT_EQ(s.fastest, fastest_name) << s.scenario;
  }
  EXPECT_EQ(study.scenarios[1].paper_least_error, "registration");
  EXPECT_THAT(format_characterization(study), HasSubstr("indoor_known     registration"));
  EXPECT_EQ(study.to_json()["points"]["indoor_known"]["vio"]["paper_fps"], 9.1);

  // Its metrics for edx check: each point's figures, and 1 where edx's ordering is the paper's.
  const nlohmann::json metrics = characterization_metrics(study.to_json(), "c.json");
  EXPECT_DOUBLE_EQ(metrics["indoor_known"]["vio"]["fps"].get<double>(),
                   study.to_json()["points"]["indoor_known"]["vio"]["fps_mean"].get<double>());
  EXPECT_EQ(metrics["indoor_unknown"]["least_error_matches"].get<double>(),
            study.scenarios[0].least_error == "slam" ? 1.0 : 0.0);
  EXPECT_FALSE(metrics["indoor_unknown"].contains("fastest_matches"));  // the paper is silent
  const std::vector<PaperTarget> targets = load_targets(default_targets_path());
  const CheckResult with = check_targets(targets, {{"characterization", metrics}}, "r");
  const CheckResult without = check_targets(targets, nlohmann::json::object(), "r");
  std::size_t characterization_targets = 0;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (!is_optional_study_metric(targets[i].metric)) continue;
    ++characterization_targets;
    EXPECT_NE(with.rows[i].verdict, Verdict::kNotRun) << targets[i].name;
    EXPECT_NE(with.rows[i].verdict, Verdict::kNotFound) << targets[i].name;
    EXPECT_EQ(without.rows[i].verdict, Verdict::kNotRun) << targets[i].name;
  }
  EXPECT_EQ(characterization_targets, 9u);
  EXPECT_EQ(without.counted(), targets.size() - 9);
  EXPECT_THROW(characterization_metrics(nlohmann::json::object(), "c.json"), std::runtime_error);

  // Traced runs are reused: the same records, no trace rewritten.
  const auto stamp = std::filesystem::last_write_time(runs[0].trace);
  const std::vector<modes::CharacterizationRun> again = modes::run_characterization(options);
  ASSERT_EQ(again.size(), runs.size());
  EXPECT_EQ(std::filesystem::last_write_time(runs[0].trace), stamp);
  EXPECT_EQ(again[3].to_json(), runs[3].to_json());
  // ... but not by a characterization of the other precision: refused before any tracing.
  options.precision = trace::Precision::kFp32;
  EXPECT_THAT([&] { modes::run_characterization(options); },
              ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr(
                  "indoor_unknown-vio-s1001.db: traced at fp64, asked for fp32 (give another "
                  "--out, or --force to trace again)")));
  EXPECT_EQ(std::filesystem::last_write_time(runs[0].trace), stamp);
}

}  // namespace
}  // namespace edx::reports
