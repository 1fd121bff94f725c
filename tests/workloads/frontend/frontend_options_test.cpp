// Frontend options: defaults are valid, bad values are named, JSON carries every field.
#include "workloads/frontend/frontend_options.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>

namespace edx::frontend {
namespace {

using ::testing::HasSubstr;

std::string validation_error(const FrontendOptions& options) {
  try {
    options.validate();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(FrontendOptions, DefaultsAreValid) { EXPECT_NO_THROW(FrontendOptions{}.validate()); }

TEST(FrontendOptions, BadValuesAreNamedWithTheExpectedRange) {
  FrontendOptions o;
  o.features_per_image = 0;
  EXPECT_EQ(validation_error(o), "frontend.features_per_image: expected an integer >= 1, got '0'");
  o = {};
  o.dr_window_px = 10;
  EXPECT_EQ(validation_error(o), "frontend.dr_window_px: expected an odd integer >= 3, got '10'");
  o = {};
  o.fast_min_threshold = 30;
  EXPECT_EQ(validation_error(o),
            "frontend.fast_min_threshold: expected an integer in [1, fast_threshold], got '30'");
  o = {};
  o.scale_factor = 1.0;
  EXPECT_THAT(validation_error(o), HasSubstr("scale_factor"));
  o = {};
  o.lk_max_iterations = 101;
  EXPECT_EQ(validation_error(o),
            "frontend.lk_max_iterations: expected an integer in [1, 100], got '101'");
  o = {};
  o.edge_margin_px = 10;
  EXPECT_THAT(validation_error(o),
              HasSubstr("edge_margin_px: expected an integer >= 19, got '10'"));
}

TEST(FrontendOptions, JsonHasEveryField) {
  FrontendOptions o;
  o.features_per_image = 777;
  o.ratio = 0.75;
  o.count_lk_iterations = false;
  const nlohmann::json j = to_json(o);
  EXPECT_EQ(j.at("features_per_image"), 777);
  EXPECT_DOUBLE_EQ(j.at("ratio").get<double>(), 0.75);
  EXPECT_EQ(j.at("count_lk_iterations"), false);
  EXPECT_EQ(j.at("dr_window_px"), 11);
  EXPECT_EQ(j.at("lk_window_px"), 12);
  EXPECT_EQ(j.at("right_features_per_image"), 2000);
  EXPECT_EQ(j.size(), 28u);  // one key per field of FrontendOptions
}

}  // namespace
}  // namespace edx::frontend
