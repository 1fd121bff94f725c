// `edx config`: the reference of every platform key is docs/CONFIG.md (checked current here,
// so CI fails when a key changes without it), covers every key the shipped platforms write,
// and a platform file resolves to JSON or to a one-line error.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/support/run_command.hpp"

namespace {

using edx::testing::built_binary;
using edx::testing::run_command;
using ::testing::HasSubstr;

const std::string kSource = EDX_SOURCE_DIR;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

long line_count(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

/// Dotted keys of every scalar in `node` ("backend.units.gemm.block").
void dotted_keys(const YAML::Node& node, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& item : node) {
    const std::string key =
        prefix.empty() ? item.first.Scalar() : prefix + "." + item.first.Scalar();
    if (item.second.IsMap()) {
      dotted_keys(item.second, key, out);
    } else {
      out.push_back(key);
    }
  }
}

TEST(ConfigCommand, ReferenceIsTheCheckedInConfigMd) {
  const auto result = run_command(built_binary("edx") + " config --reference");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(result.out == read_file(kSource + "/docs/CONFIG.md"))
      << "docs/CONFIG.md is stale: run `./build/bin/edx config --reference > docs/CONFIG.md`";
}

TEST(ConfigCommand, ReferenceCoversEveryKeyOfTheShippedPlatforms) {
  const auto result = run_command(built_binary("edx") + " config --reference");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* file : {"edx_car.yaml", "edx_drone.yaml"}) {
    std::vector<std::string> keys;
    dotted_keys(YAML::LoadFile(kSource + "/configs/" + file), "", keys);
    ASSERT_GT(keys.size(), 50u) << file;
    for (std::string key : keys) {
      // A unit instance's keys are documented under its kind: backend.units.<name>.block,
      // frontend.units.<task>.tests_per_cycle.
      for (const auto& [units, placeholder] :
           {std::pair<std::string, std::string>{"backend.units.", "<name>"},
            {"frontend.units.", "<task>"}}) {
        if (!key.starts_with(units)) continue;
        const std::size_t dot = key.find('.', units.size());
        key = units + placeholder + key.substr(dot);
      }
      // The baseline's host has the keys of `host:` (its reference row says so).
      if (key.starts_with("baseline_host.")) key = "host." + key.substr(14);
      EXPECT_THAT(result.out, HasSubstr("| `" + key + "` |")) << file;
    }
  }
}

TEST(ConfigCommand, ResolvesAPlatformFileToJson) {
  const auto result =
      run_command(built_binary("edx") + " config " + kSource + "/configs/edx_drone.yaml");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json j = nlohmann::json::parse(result.out);
  EXPECT_EQ(j["name"], "edx_drone");
  EXPECT_EQ(j["backend"]["units"]["gemm"]["block"], 2);
  EXPECT_EQ(j["backend"]["precision"], "fp64");
  EXPECT_EQ(j["link"]["kind"], "dma");
  EXPECT_EQ(j["link"]["name"], "axi4");
  EXPECT_EQ(j["memory"]["kind"], "bram");
  EXPECT_EQ(j["system"]["drop"], "oldest");  // a default filled in
}

TEST(ConfigCommand, BadInputIsOneLineAndNonZero) {
  const std::string dir = ::testing::TempDir() + "edx_config_command";
  std::filesystem::create_directories(dir);
  {
    std::ofstream bad(dir + "/bad.yaml");
    bad << "name: x\nbackend:\n  precision: fp16\n";
  }
  auto result = run_command(built_binary("edx") + " config " + dir + "/bad.yaml");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
  EXPECT_THAT(result.err,
              HasSubstr("bad.yaml:3: backend.precision: expected fp64 or fp32, got 'fp16'"));
  EXPECT_TRUE(result.out.empty());

  result = run_command(built_binary("edx") + " config");  // neither a file nor --reference
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
  result = run_command(built_binary("edx") + " config --reference " + kSource +
                       "/configs/edx_car.yaml");  // both
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
}

}  // namespace
