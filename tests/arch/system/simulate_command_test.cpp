// `edx simulate` end to end: a real trace of the KITTI 01 excerpt at Edx-Car's 1280x720 through
// configs/edx_car.yaml, checked against the paper's Edx-Car frontend figures (Sec. VII-C) that
// depend only on the trace's work counts (the CPU baseline depends on the host that traced).
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::arch {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kEdx = edx::testing::built_binary("edx");
const fs::path kKitti =
    fs::path(EDX_SHARED_DATA_DIR) / "kitti_odometry_excerpt" / "sequences" / "01";
const fs::path kCarConfig = fs::path(EDX_SOURCE_DIR) / "configs" / "edx_car.yaml";

/// A trace of the first `frames` KITTI frames at 1280x720, made once per test binary.
const fs::path& car_trace() {
  static testing::TempDir dir;
  static const fs::path path = [] {
    const fs::path out = dir.path() / "kitti720.db";
    const auto r = edx::testing::run_command(fmt::format(
        "{} trace --dataset {} --format kitti --resolution 1280x720 --frames 20 --out {}", kEdx,
        kKitti.string(), out.string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }();
  return path;
}

/// |simulated / paper - 1| <= 10%.
void expect_within_10_percent(double simulated, double paper, const char* what) {
  EXPECT_NEAR(simulated / paper, 1.0, 0.10)
      << what << ": simulated " << simulated << ", paper " << paper;
}

TEST(SimulateCommand, ReproducesTheEdxCarFrontendFigures) {
  const auto r =
      edx::testing::run_command(fmt::format("{} simulate --config {} --trace {} --json", kEdx,
                                            kCarConfig.string(), car_trace().string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out)["frontend"];
  EXPECT_EQ(j["frames"], 20);
  EXPECT_EQ(j["resolution"], "1280x720");
  expect_within_10_percent(j["accel_ms"]["mean"], 42.7, "frontend latency (ms)");
  expect_within_10_percent(j["fps_without_pipelining"], 26.1, "FPS without FE/SM pipelining");
  expect_within_10_percent(j["fps_with_pipelining"], 44.0, "FPS with FE/SM pipelining");
  // SM dominates the frontend latency; TM is hidden behind the critical path.
  EXPECT_GT(j["sm_ms"]["mean"].get<double>(), j["fe_ms"]["mean"].get<double>());
  EXPECT_LT(j["tm_ms"]["mean"].get<double>(), j["sm_ms"]["mean"].get<double>());
}

TEST(SimulateCommand, WritesATimeline) {
  testing::TempDir dir;
  const fs::path timeline = dir.path() / "frontend.json";
  const auto r = edx::testing::run_command(fmt::format(
      "{} simulate --config {} --trace {} --timeline {} --timeline-first 2 --timeline-frames 3",
      kEdx, kCarConfig.string(), car_trace().string(), timeline.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("speedup"));
  std::ifstream in(timeline);
  const nlohmann::json doc = nlohmann::json::parse(in);
  int frames = 0;
  for (const auto& e : doc["traceEvents"]) {
    if (e["ph"] == "X" && e["name"].get<std::string>().starts_with("frame ")) ++frames;
  }
  EXPECT_EQ(frames, 3);
}

TEST(SimulateCommand, BadInputExitsOneNamingTheFile) {
  testing::TempDir dir;
  const fs::path bad = dir.path() / "bad.yaml";
  std::ofstream(bad) << "name: x\nfrontend:\n  clock_mhz: -3\n";
  auto r = edx::testing::run_command(
      fmt::format("{} simulate --config {} --trace {}", kEdx, bad.string(), car_trace().string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("bad.yaml:3: frontend.clock_mhz"));
  r = edx::testing::run_command(fmt::format("{} simulate --config {} --trace {}", kEdx,
                                            kCarConfig.string(), (dir.path() / "no.db").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("no.db"));
  r = edx::testing::run_command(fmt::format("{} simulate --trace x.db", kEdx));
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace edx::arch
