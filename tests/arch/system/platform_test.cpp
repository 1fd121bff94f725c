// Platform YAML: fields over defaults, and errors that name the file, line and key.
#include "arch/system/platform.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace edx::arch {
namespace {

using ::testing::HasSubstr;

std::string error_of(const std::string& yaml) {
  try {
    Platform::parse(yaml, "p.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Platform, ReadsFieldsOverTheDefaults) {
  const Platform p = Platform::parse(
      "name: car\nhost:\n  frontend_time_scale: 2.5\n  provenance: calibrated\nfrontend:\n"
      "  clock_mhz: 200\n  pipeline_fe_sm: false\n  mo_comparators: 8\n",
      "p.yaml");
  EXPECT_EQ(p.name, "car");
  EXPECT_DOUBLE_EQ(p.host.frontend_time_scale, 2.5);
  EXPECT_EQ(p.host.provenance, "calibrated");
  EXPECT_DOUBLE_EQ(p.frontend.clock_mhz, 200);
  EXPECT_FALSE(p.frontend.pipeline_fe_sm);
  EXPECT_EQ(p.frontend.mo_comparators, 8);
  EXPECT_EQ(p.frontend.fd_stencil, FrontendConfig{}.fd_stencil);
  EXPECT_EQ(p.to_json()["frontend"]["clock_mhz"], 200.0);
}

TEST(Platform, BadInputNamesFileLineAndKey) {
  EXPECT_EQ(error_of("name: car\nfrontend:\n  clock_mhz: fast\n"),
            "p.yaml:3: frontend.clock_mhz: expected a number > 0, got 'fast'");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  clok_mhz: 100\n"),
            "p.yaml:3: frontend.clok_mhz: unknown key");
  EXPECT_EQ(error_of("name: car\nfrontend:\n  fd_stencil: 4\n"),
            "p.yaml:3: frontend.fd_stencil: expected an odd size >= 3");
  EXPECT_EQ(error_of("name: car\nhost: 3\n"), "p.yaml:2: platform.host: expected a map of keys");
  EXPECT_EQ(error_of("name: car\nbackend_units: {}\n"),
            "p.yaml:2: platform.backend_units: unknown key");
  EXPECT_THAT(error_of("frontend: {}\n"), HasSubstr("platform.name: required"));
  EXPECT_THAT(error_of("name: [unclosed\n"), HasSubstr("p.yaml:"));
  EXPECT_THAT(error_of("name: car\nfrontend:\n  mo_comparators: 0\n"),
              HasSubstr("p.yaml:3: frontend.mo_comparators: expected an integer >= 1"));
}

TEST(Platform, MissingFileIsNamed) {
  try {
    Platform::load("/nonexistent/edx_car.yaml");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/edx_car.yaml"));
  }
}

}  // namespace
}  // namespace edx::arch
