// Mixed sequences (workloads/modes/mix.hpp): the paper's scenario shares and data generation.
#include "workloads/modes/mix.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "tests/support/temp_dir.hpp"
#include "workloads/modes/sweep_workload.hpp"

namespace edx::modes {
namespace {

TEST(PaperMix, HasThePapersScenarioShares) {
  const MixPlan plan = make_mix("paper", 400, {640, 480}, 7);
  ASSERT_EQ(plan.segments.size(), 3u);
  EXPECT_EQ(plan.total_frames(), 400);
  EXPECT_EQ(plan.segments[0].frames, 200);  // 50 % outdoor
  EXPECT_EQ(plan.segments[0].scenario, trace::Scenario::OutdoorUnknown);
  EXPECT_EQ(plan.segments[1].frames, 100);  // 25 % indoor without a map
  EXPECT_EQ(plan.segments[1].scenario, trace::Scenario::IndoorUnknown);
  EXPECT_EQ(plan.segments[2].frames, 100);  // 25 % indoor with a map
  EXPECT_EQ(plan.segments[2].scenario, trace::Scenario::IndoorKnown);
  // The mapped and the localized indoor runs are two runs of one world.
  EXPECT_EQ(plan.segments[1].world, plan.segments[2].world);
  EXPECT_EQ(plan.segments[1].run, "map");
  EXPECT_EQ(plan.segments[2].run, "loc");
  // Odd totals: indoor segments get the floor of a quarter, outdoor the rest.
  const MixPlan odd = make_mix("paper", 10, {640, 480}, 7);
  EXPECT_EQ(odd.segments[0].frames, 6);
  EXPECT_EQ(odd.segments[1].frames, 2);
  EXPECT_EQ(odd.total_frames(), 10);
}

TEST(PaperMix, RejectsUnknownNamesAndTooFewFrames) {
  EXPECT_THROW(make_mix("lab", 100, {640, 480}, 1), std::runtime_error);
  EXPECT_THROW(make_mix("paper", 7, {640, 480}, 1), std::runtime_error);
}

TEST(PaperMix, GeneratesEachWorldOnceAndReusesIt) {
  const edx::testing::TempDir dir;
  const MixPlan plan = make_mix("paper", 8, {160, 120}, 3);
  generate_mix_data(plan, dir.path());
  for (const MixSegment& s : plan.segments) {
    const auto mav0 = segment_mav0(plan, s, dir.path());
    EXPECT_TRUE(std::filesystem::exists(mav0 / "cam0" / "data.csv")) << mav0;
    EXPECT_EQ(std::filesystem::exists(mav0 / "gps0"), s.name == "outdoor") << mav0;
  }
  const auto stamp = std::filesystem::last_write_time(
      segment_mav0(plan, plan.segments[0], dir.path()) / "cam0" / "data.csv");
  generate_mix_data(plan, dir.path());  // everything there: nothing rewritten
  EXPECT_EQ(std::filesystem::last_write_time(segment_mav0(plan, plan.segments[0], dir.path()) /
                                             "cam0" / "data.csv"),
            stamp);
}

}  // namespace
}  // namespace edx::modes

// ---- workload points of sweeps (sweep_workload.hpp) ----

namespace edx::modes {
namespace {

TEST(SweepWorkload, TextAndNumbersResolveToOneTypedForm) {
  const SweepWorkload w = SweepWorkload::from_json(
      {{"features", "500"}, {"resolution", "1280x720"}, {"frames", 40}, {"msckf_window", 15.0}});
  EXPECT_EQ(w.features, 500);
  EXPECT_EQ(w.resolution.width, 1280);
  EXPECT_EQ(w.resolution.height, 720);
  EXPECT_EQ(w.frames, 40);
  EXPECT_EQ(w.msckf_window, 15);
  EXPECT_EQ(w.slam_window, 10);  // default
  EXPECT_EQ(w.to_json(), SweepWorkload::from_json(w.to_json()).to_json());
  EXPECT_EQ(
      w.to_json(),
      SweepWorkload::from_json(
          {{"features", 500}, {"resolution", "1280x720"}, {"frames", "40"}, {"msckf_window", "15"}})
          .to_json());
  EXPECT_EQ(SweepWorkload::from_json(nlohmann::json::object()).to_json()["mix"], "paper");
  EXPECT_TRUE(SweepWorkload::from_json(nlohmann::json::object()).to_json()["map_frames"].is_null());
  EXPECT_EQ(SweepWorkload::from_json({{"map_frames", "150"}}).map_frames, 150);
}

TEST(SweepWorkload, BadValuesNameTheParameter) {
  const auto error = [](const nlohmann::json& j) {
    try {
      SweepWorkload::from_json(j);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error({{"features", "0"}}), "features: expected an integer in [1, 100000], got '0'");
  EXPECT_EQ(error({{"frames", "12.5"}}), "frames: expected an integer in [8, 1000000], got '12.5'");
  EXPECT_EQ(error({{"slam_window", 1}}), "slam_window: expected an integer in [2, 1000], got '1'");
  EXPECT_EQ(error({{"mix", "city"}}),
            "mix: expected paper, outdoor, indoor_unknown or indoor_known, got 'city'");
  EXPECT_EQ(error({{"map_frames", 1}}),
            "map_frames: expected an integer in [2, 1000000] or default, got '1'");
  EXPECT_EQ(error({{"resolution", "wide"}}),
            "resolution: expected WIDTHxHEIGHT in pixels (e.g. 640x480), got 'wide'");
  EXPECT_EQ(error({{"speed", 3}}),
            "speed: unknown key (expected one of: mix, frames, resolution, features, seed, "
            "msckf_window, slam_window, precision, map_frames)");
  EXPECT_EQ(error({{"precision", "fp16"}}), "precision: expected fp64 or fp32, got 'fp16'");
}

}  // namespace
}  // namespace edx::modes

namespace edx::modes {
namespace {

TEST(MixPlan, ScenarioMixesAndTheMapSize) {
  const MixPlan outdoor = make_mix("outdoor", 100, {640, 480}, 1);
  ASSERT_EQ(outdoor.segments.size(), 1u);
  EXPECT_EQ(outdoor.segments[0].scenario, trace::Scenario::OutdoorUnknown);
  EXPECT_EQ(outdoor.total_frames(), 100);
  const MixPlan unknown = make_mix("indoor_unknown", 100, {640, 480}, 1);
  ASSERT_EQ(unknown.segments.size(), 1u);
  EXPECT_EQ(unknown.segments[0].world_scenario, synthetic::Scenario::kIndoorUnknown);
  const MixPlan known = make_mix("indoor_known", 101, {640, 480}, 1);
  ASSERT_EQ(known.segments.size(), 2u);
  EXPECT_EQ(known.segments[0].frames, 50);  // mapping
  EXPECT_EQ(known.segments[1].frames, 51);  // registering in the map
  EXPECT_EQ(known.segments[0].world, known.segments[1].world);
  // The paper mix with a longer mapping run: the map grows, the other segments stay.
  const MixPlan paper = make_mix("paper", 400, {640, 480}, 1);
  const MixPlan big_map = make_mix("paper", 400, {640, 480}, 1, 300);
  EXPECT_EQ(big_map.segments[0].frames, paper.segments[0].frames);
  EXPECT_EQ(big_map.segments[1].frames, 300);
  EXPECT_EQ(big_map.segments[2].frames, paper.segments[2].frames);
  EXPECT_EQ(big_map.total_frames(), 600);
  // Both runs of the warehouse live in one world folder, named for both lengths.
  const std::filesystem::path dir = "/data";
  EXPECT_EQ(segment_mav0(big_map, big_map.segments[1], dir).parent_path().parent_path(),
            segment_mav0(big_map, big_map.segments[2], dir).parent_path().parent_path());
  EXPECT_EQ(segment_mav0(big_map, big_map.segments[1], dir).parent_path().parent_path().filename(),
            "indoor_known-640x480-f100-m300-s1");
  EXPECT_EQ(segment_mav0(paper, paper.segments[1], dir).parent_path().parent_path().filename(),
            "indoor_known-640x480-f100-s1");
  EXPECT_THROW(make_mix("outdoor", 100, {640, 480}, 1, 50), std::runtime_error);
  EXPECT_THROW(make_mix("paper", 100, {640, 480}, 1, 1), std::runtime_error);
}

}  // namespace
}  // namespace edx::modes
