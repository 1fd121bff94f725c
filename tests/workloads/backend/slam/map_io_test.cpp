// The SLAM map file: round trip, and one-line errors naming the file and what was expected.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/support/temp_dir.hpp"
#include "workloads/backend/slam/map.hpp"

namespace edx::backend::slam {
namespace {

Map sample_map() {
  Map map;
  map.source = "synthetic:test";
  map.camera.width = 752;
  map.camera.height = 480;
  map.camera.fx = map.camera.fy = 458.5;
  map.camera.cx = 367.2;
  map.camera.cy = 248.4;
  map.camera.baseline_m = 0.11;
  map.camera.T_body_left.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  for (int k = 0; k < 2; ++k) {
    MapKeyframe kf;
    kf.id = 10 + k;
    kf.t_ns = 1'600'000'000'000'000'000 + k * 50'000'000;
    kf.frame_index = static_cast<std::size_t>(3 * k);
    kf.T_world_body.linear() = Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d::UnitZ()).matrix();
    kf.T_world_body.translation() = Eigen::Vector3d(k * 0.5, 1.0, -0.25);
    for (int p = 0; p < 3; ++p) {
      MapKeypoint kp;
      kp.track_id = 100 + p;
      kp.left = {10.5 + p, 20.25};
      if (p != 1) kp.right = Eigen::Vector2d(5.5 + p, 20.25);
      kp.depth_m = p != 1 ? 3.5 : 0.0;
      kp.octave = p;
      kp.angle_deg = 12.5;
      kp.descriptor.fill(static_cast<std::uint8_t>(17 * p + k));
      kf.keypoints.push_back(kp);
    }
    map.keyframes.push_back(kf);
  }
  MapLandmark l;
  l.id = 4;
  l.track_id = 100;
  l.position = {1.25, -2.5, 3.75};
  l.descriptor.fill(0xab);
  l.observations = {{10, 0}, {11, 0}};
  map.landmarks.push_back(l);
  return map;
}

TEST(SlamMap, RoundTrip) {
  const testing::TempDir dir;
  const Map map = sample_map();
  save_map(map, dir.path() / "map.json");
  const Map loaded = load_map(dir.path() / "map.json");
  EXPECT_EQ(loaded.source, map.source);
  EXPECT_EQ(loaded.camera.width, 752);
  EXPECT_DOUBLE_EQ(loaded.camera.fx, 458.5);
  EXPECT_TRUE(loaded.camera.T_body_left.isApprox(map.camera.T_body_left, 1e-12));
  ASSERT_EQ(loaded.keyframes.size(), 2u);
  EXPECT_EQ(loaded.keyframes[1].id, 11);
  EXPECT_EQ(loaded.keyframes[1].t_ns, map.keyframes[1].t_ns);
  EXPECT_TRUE(loaded.keyframes[1].T_world_body.isApprox(map.keyframes[1].T_world_body, 1e-12));
  ASSERT_EQ(loaded.keyframes[1].keypoints.size(), 3u);
  EXPECT_FALSE(loaded.keyframes[1].keypoints[1].right.has_value());
  EXPECT_EQ(loaded.keyframes[1].keypoints[2].right->x(), 7.5);
  EXPECT_EQ(loaded.keyframes[1].keypoints[2].descriptor, map.keyframes[1].keypoints[2].descriptor);
  ASSERT_EQ(loaded.landmarks.size(), 1u);
  EXPECT_EQ(loaded.landmarks[0].position, map.landmarks[0].position);
  EXPECT_EQ(loaded.landmarks[0].descriptor, map.landmarks[0].descriptor);
  EXPECT_EQ(loaded.landmarks[0].observations, map.landmarks[0].observations);
}

/// Saves the sample map, edits its JSON, and returns load_map's error.
std::string load_error(const std::function<void(nlohmann::json&)>& edit) {
  const testing::TempDir dir;
  const auto file = dir.path() / "map.json";
  save_map(sample_map(), file);
  nlohmann::json j;
  std::ifstream(file) >> j;
  edit(j);
  std::ofstream(file) << j.dump();
  try {
    load_map(file);
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(file.string()));
    return e.what();
  }
  return "no error";
}

TEST(SlamMap, BadFilesAreRejectedWithTheFieldAndWhatWasExpected) {
  using ::testing::HasSubstr;
  EXPECT_THAT(load_error([](auto& j) { j["version"] = 2; }), HasSubstr("map.version: expected 1"));
  EXPECT_THAT(load_error([](auto& j) { j["format"] = "other"; }),
              HasSubstr("map.format: expected \"edx-slam-map\""));
  EXPECT_THAT(load_error([](auto& j) { j["keyframes"][1].erase("T_world_body"); }),
              HasSubstr("map.keyframes[1].T_world_body: expected a value (missing)"));
  EXPECT_THAT(load_error([](auto& j) { j["keyframes"][0]["keypoints"][2]["descriptor"] = "xyz"; }),
              HasSubstr("map.keyframes[0].keypoints[2].descriptor: expected a string of 64"));
  EXPECT_THAT(load_error([](auto& j) {
                j["landmarks"][0]["observations"][1] = {11, 3};
              }),
              HasSubstr("map.landmarks[0].observations[1]: expected a keypoint index in [0, 3)"));
  EXPECT_THAT(load_error([](auto& j) {
                j["landmarks"][0]["observations"][0] = {99, 0};
              }),
              HasSubstr("expected the id of a keyframe"));
  EXPECT_THAT(load_error([](auto& j) { j["camera"]["T_body_left"] = {1, 2, 3, 2, 0, 0, 0}; }),
              HasSubstr("unit quaternion"));
}

TEST(SlamMap, NotJsonAndMissingFile) {
  const testing::TempDir dir;
  std::ofstream(dir.path() / "bad.json") << "edx map\n";
  EXPECT_THROW(load_map(dir.path() / "bad.json"), std::runtime_error);
  EXPECT_THROW(load_map(dir.path() / "missing.json"), std::runtime_error);
}

}  // namespace
}  // namespace edx::backend::slam
