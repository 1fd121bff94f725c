// The mode switch (workloads/modes/mode_switch.hpp): the paper's taxonomy, GPS quality read from
// the GPS stream, and map usefulness from registration outcomes.
#include "workloads/modes/mode_switch.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace edx::modes {
namespace {

using trace::BackendMode;

constexpr std::int64_t kSecond = 1'000'000'000;

/// Fixes every 100 ms from t0 to t1 (inclusive) with the given sigma.
std::vector<datasets::GpsFix> fixes(std::int64_t t0, std::int64_t t1, double sigma = 0.5) {
  std::vector<datasets::GpsFix> out;
  for (std::int64_t t = t0; t <= t1; t += kSecond / 10) out.push_back({t, {0, 0, 0}, sigma});
  return out;
}

TEST(ModeTaxonomy, FollowsThePaper) {
  EXPECT_EQ(choose_mode(true, MapUse::kNone), BackendMode::Vio);
  EXPECT_EQ(choose_mode(true, MapUse::kUsable), BackendMode::Vio);  // GPS wins outdoors
  EXPECT_EQ(choose_mode(false, MapUse::kUsable), BackendMode::Registration);
  EXPECT_EQ(choose_mode(false, MapUse::kProbing), BackendMode::Registration);
  EXPECT_EQ(choose_mode(false, MapUse::kUnusable), BackendMode::Slam);
  EXPECT_EQ(choose_mode(false, MapUse::kNone), BackendMode::Slam);
}

TEST(GpsQuality, CountsGoodFixesInTheWindow) {
  ModeSwitchOptions o;  // >= 5 fixes of sigma <= 5 m in the last 1 s
  const auto all = fixes(0, 10 * kSecond);
  EXPECT_TRUE(gps_usable(all, 5 * kSecond, o));
  // At t = 0.4 s only 5 fixes (0, 0.1, ..., 0.4) have arrived: just enough.
  EXPECT_TRUE(gps_usable(all, 4 * kSecond / 10, o));
  EXPECT_FALSE(gps_usable(all, 3 * kSecond / 10, o));
  // 1.45 s after the last fix, the window (0.45 s, 1.45 s] before it holds none of them.
  EXPECT_FALSE(gps_usable(all, 10 * kSecond + 1450 * kSecond / 1000, o));
  // 0.55 s after the last fix the window (9.55 s, 10.55 s] holds 5 fixes (9.6 ... 10.0).
  EXPECT_TRUE(gps_usable(all, 10 * kSecond + 550 * kSecond / 1000, o));
  EXPECT_FALSE(gps_usable(all, 10 * kSecond + 650 * kSecond / 1000, o));
  EXPECT_FALSE(gps_usable({}, 5 * kSecond, o));
}

TEST(GpsQuality, IgnoresFixesWorseThanTheLimit) {
  ModeSwitchOptions o;
  o.gps_max_sigma_m = 2.0;
  EXPECT_FALSE(gps_usable(fixes(0, 2 * kSecond, 10.0), kSecond, o));  // multipath-grade fixes
  EXPECT_TRUE(gps_usable(fixes(0, 2 * kSecond, 1.5), kSecond, o));
}

TEST(ModeSwitch, ProbesAMapThenKeepsOrDropsIt) {
  ModeSwitchOptions o;
  o.map_probe_frames = 2;
  o.registration_failures_to_fall_back = 3;
  ModeSwitch probe_fails(o, true);
  EXPECT_EQ(probe_fails.decide(0, {}).mode, BackendMode::Registration);
  probe_fails.report_registration(false);
  EXPECT_EQ(probe_fails.map(), MapUse::kProbing);
  probe_fails.report_registration(false);  // second failure of the probe: unusable
  EXPECT_EQ(probe_fails.map(), MapUse::kUnusable);
  EXPECT_EQ(probe_fails.decide(0, {}).mode, BackendMode::Slam);

  ModeSwitch usable(o, true);
  usable.report_registration(false);
  usable.report_registration(true);
  EXPECT_EQ(usable.map(), MapUse::kUsable);
  usable.report_registration(false);
  usable.report_registration(false);
  usable.report_registration(true);  // a success resets the count
  usable.report_registration(false);
  usable.report_registration(false);
  EXPECT_EQ(usable.map(), MapUse::kUsable);
  usable.report_registration(false);  // third failure in a row
  EXPECT_EQ(usable.map(), MapUse::kUnusable);
  EXPECT_EQ(usable.decide(0, {}).mode, BackendMode::Slam);
  usable.map_loaded();  // a new map: probing again
  EXPECT_EQ(usable.decide(0, {}).mode, BackendMode::Registration);
}

TEST(ModeSwitch, GpsOverridesTheMapAndNoMapMeansSlam) {
  const auto stream = fixes(0, 3 * kSecond);
  ModeSwitch with_map(ModeSwitchOptions{}, true);
  const ModeDecision outdoors = with_map.decide(2 * kSecond, stream);
  EXPECT_TRUE(outdoors.gps_usable);
  EXPECT_EQ(outdoors.mode, BackendMode::Vio);
  EXPECT_EQ(with_map.decide(5 * kSecond, stream).mode, BackendMode::Registration);
  ModeSwitch without_map(ModeSwitchOptions{}, false);
  EXPECT_EQ(without_map.decide(5 * kSecond, stream).mode, BackendMode::Slam);
  without_map.report_registration(true);  // no map: nothing to report on
  EXPECT_EQ(without_map.map(), MapUse::kNone);
}

TEST(ModeSwitch, RejectsBadOptions) {
  ModeSwitchOptions o;
  o.gps_min_fixes = 0;
  EXPECT_THROW(ModeSwitch(o, false), std::runtime_error);
  o = {};
  o.gps_window_s = 0;
  try {
    o.validate();
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gps_window_s"), std::string::npos);
  }
}

}  // namespace
}  // namespace edx::modes
