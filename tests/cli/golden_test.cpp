// Golden results (issue 17; Timeloop's ref_outputs): `edx simulate --json` and `edx check --json`
// of Edx-Car and Edx-Drone on the committed reference trace tests/data/golden/golden_mix.db must
// equal the committed expected outputs, numbers to 1e-9 relative and everything else exactly. A
// model change that moves them regenerates them (tests/data/golden/update.sh) in the same commit.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Appends to `diffs` every place (as a JSON pointer) where `actual` differs from `expected`.
void compare(const json& expected, const json& actual, const std::string& at,
             std::vector<std::string>& diffs) {
  if (expected.is_number() && actual.is_number()) {
    const double e = expected.get<double>(), a = actual.get<double>();
    if (!(std::abs(a - e) <= 1e-9 * std::max(std::abs(a), std::abs(e)) + 1e-12)) {
      diffs.push_back(fmt::format("{}: expected {}, got {}", at, expected.dump(), actual.dump()));
    }
    return;
  }
  if (expected.type() != actual.type()) {
    diffs.push_back(fmt::format("{}: expected {}, got {}", at, expected.dump(), actual.dump()));
    return;
  }
  if (expected.is_object()) {
    for (const auto& [key, value] : expected.items()) {
      if (!actual.contains(key)) {
        diffs.push_back(fmt::format("{}/{}: missing", at, key));
      } else {
        compare(value, actual[key], at + "/" + key, diffs);
      }
    }
    for (const auto& [key, value] : actual.items()) {
      if (!expected.contains(key)) diffs.push_back(fmt::format("{}/{}: not expected", at, key));
    }
  } else if (expected.is_array()) {
    if (expected.size() != actual.size()) {
      diffs.push_back(
          fmt::format("{}: expected {} elements, got {}", at, expected.size(), actual.size()));
      return;
    }
    for (std::size_t i = 0; i < expected.size(); ++i) {
      compare(expected[i], actual[i], fmt::format("{}/{}", at, i), diffs);
    }
  } else if (expected != actual) {
    diffs.push_back(fmt::format("{}: expected {}, got {}", at, expected.dump(), actual.dump()));
  }
}

TEST(Compare, FindsEveryDifference) {
  std::vector<std::string> diffs;
  compare(json::parse(R"({"a": 1.0, "b": [1, "x"], "c": true})"),
          json::parse(R"({"a": 1.0000000000001, "b": [1, "x"], "c": true})"), "", diffs);
  EXPECT_TRUE(diffs.empty());
  compare(json::parse(R"({"a": 1.0, "b": [1, "x"], "c": true, "d": 0})"),
          json::parse(R"({"a": 1.001, "b": [1, "y"], "c": false, "e": 0})"), "", diffs);
  EXPECT_EQ(diffs.size(), 5u);  // a, b/1, c, d missing, e not expected
}

TEST(Golden, SimulateAndCheckOfBothPlatformsMatchTheReferenceOutputs) {
  const fs::path golden = fs::path(EDX_SOURCE_DIR) / "tests" / "data" / "golden";
  const TempDir dir;
  // Run where the trace is named as when the outputs were made (its name is in the output).
  fs::copy_file(golden / "golden_mix.db", dir.path() / "golden_mix.db");
  for (const char* platform : {"car", "drone"}) {
    for (const char* command : {"simulate", "check"}) {
      SCOPED_TRACE(fmt::format("edx {} of edx_{}", command, platform));
      const fs::path config =
          fs::path(EDX_SOURCE_DIR) / "configs" / fmt::format("edx_{}.yaml", platform);
      const CommandResult r = run_command(
          fmt::format("cd '{}' && '{}' {} --config '{}' --trace golden_mix.db --json",
                      dir.path().string(), built_binary("edx"), command, config.string()));
      // check exits 1 when a paper target is missed; its table is compared all the same.
      ASSERT_TRUE(r.exit_code == 0 || (r.exit_code == 1 && std::string(command) == "check"))
          << r.err;
      const json expected =
          json::parse(read_text_file(golden / fmt::format("{}_{}.json", platform, command)));
      std::vector<std::string> diffs;
      compare(expected, json::parse(r.out), "", diffs);
      std::string shown;
      for (std::size_t i = 0; i < std::min<std::size_t>(diffs.size(), 10); ++i) {
        shown += diffs[i] + "\n";
      }
      EXPECT_TRUE(diffs.empty()) << diffs.size()
                                 << " differences (regenerate with tests/data/golden/update.sh "
                                    "when the model changed on purpose), the first:\n"
                                 << shown;
    }
  }
}

TEST(HostCostsCommand, FitsATableOnTheReferenceTraceAndChecksTheTraceAgainstIt) {
  const fs::path golden = fs::path(EDX_SOURCE_DIR) / "tests" / "data" / "golden";
  const TempDir dir;
  const fs::path table = dir.path() / "costs.yaml";
  const CommandResult fit = run_command(
      fmt::format("'{}' host-costs fit --trace '{}' --out '{}' --provenance test",
                  built_binary("edx"), (golden / "golden_mix.db").string(), table.string()));
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("kalman_gain"), std::string::npos) << fit.out;
  const CommandResult check = run_command(
      fmt::format("'{}' host-costs check --trace '{}' --costs '{}' --json", built_binary("edx"),
                  (golden / "golden_mix.db").string(), table.string()));
  ASSERT_EQ(check.exit_code, 0) << check.err;
  const json kinds = json::parse(check.out).at(0).at("kinds");
  // Fitted on this very trace: per part, the modeled total is the measured one within the few
  // per cent that dropping negative costs can move it.
  const std::vector<std::string> frontend = {"FD", "IF", "FC",  "MO",
                                             "DR", "DC", "LSS", "frontend_rest"};
  double measured = 0, modeled = 0;
  std::size_t seen = 0;
  for (const json& k : kinds) {
    if (std::find(frontend.begin(), frontend.end(), k.at("kind")) == frontend.end()) continue;
    ++seen;
    measured += k.at("measured_ns_per_suite_ms").get<double>();
    modeled += k.at("modeled_ns_per_suite_ms").get<double>();
  }
  EXPECT_EQ(seen, frontend.size());
  EXPECT_NEAR(modeled, measured, 0.05 * measured);
}

TEST(CheckCommand, TheSpeedupOverABaselineIsItsCpuRunOverTheAcceleratedRun) {
  const fs::path trace = fs::path(EDX_SOURCE_DIR) / "tests" / "data" / "golden" / "golden_mix.db";
  const fs::path configs = fs::path(EDX_SOURCE_DIR) / "configs";
  const auto simulate = [&](const fs::path& config) {
    const CommandResult r =
        run_command(fmt::format("'{}' simulate --config '{}' --trace '{}' --json",
                                built_binary("edx"), config.string(), trace.string()));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return json::parse(r.out).at("system");
  };
  const json car = simulate(configs / "edx_car.yaml");
  const json single = simulate(configs / "baselines" / "car_single_core.yaml");
  const double accelerated = car.at("accelerated").at("modes").at("all").at("e2e_ms").at("mean");
  const double one_core = single.at("baseline").at("modes").at("all").at("e2e_ms").at("mean");
  const double four_cores = car.at("baseline").at("modes").at("all").at("e2e_ms").at("mean");
  EXPECT_GT(one_core, four_cores);  // the frontend's chains one after the other
  const CommandResult check =
      run_command(fmt::format("'{}' check --config '{}' --trace '{}' --json", built_binary("edx"),
                              (configs / "edx_car.yaml").string(), trace.string()));
  ASSERT_TRUE(check.exit_code == 0 || check.exit_code == 1) << check.err;
  std::map<std::string, double> simulated;
  const json table = json::parse(check.out);
  for (const json& row : table.at("rows")) {
    if (row.at("simulated").is_number()) {
      simulated[row.at("name").get<std::string>()] = row.at("simulated").get<double>();
    }
  }
  EXPECT_NEAR(simulated.at("speedup over single-core w/o ROS"), one_core / accelerated, 1e-9);
  EXPECT_NEAR(simulated.at("speedup over multi-core w/o ROS"), four_cores / accelerated, 1e-9);
}

}  // namespace
}  // namespace edx::testing
