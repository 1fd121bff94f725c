// SlamOptions: defaults are valid, bad values name the field, to_json lists every option.
#include "workloads/backend/slam/slam_options.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace edx::backend::slam {
namespace {

TEST(SlamOptions, DefaultsAreValidAndPrintable) {
  const SlamOptions options;
  EXPECT_NO_THROW(options.validate());
  const nlohmann::json j = options.to_json();
  EXPECT_EQ(j.at("window_size"), 10);
  EXPECT_EQ(j.at("estimate_disparity_offset"), true);
  EXPECT_EQ(j.at("stereo_max_depth_baselines"), 0.0);
  EXPECT_EQ(j.size(), 23u);
}

TEST(SlamOptions, BadValuesNameTheField) {
  SlamOptions options;
  options.window_size = 1;
  try {
    options.validate();
    FAIL() << "window_size 1 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("window_size"));
  }
  options = SlamOptions{};
  options.keyframe_tracked_ratio = 1.5;
  EXPECT_THROW(options.validate(), std::runtime_error);
}

}  // namespace
}  // namespace edx::backend::slam
