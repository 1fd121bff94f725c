// `edx vocab` end to end on the EuRoC excerpt: a small vocabulary is trained, saved and refused
// as an existing output; bad datasets exit 1 naming them.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const std::string kEdx = testing::built_binary("edx");
const fs::path kEuroc = fs::path(EDX_SHARED_DATA_DIR) / "euroc_v101_micro";

TEST(VocabCommand, TrainsSavesAndRefusesToOverwrite) {
  testing::TempDir dir;
  const fs::path out = dir.path() / "vocab.bin";
  const std::string command =
      fmt::format("{} vocab --datasets {} --stride 20 --branching 4 --depth 3 --out {} --json",
                  kEdx, kEuroc.string(), out.string());
  const auto r = testing::run_command(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["summary"]["images"], 5);  // frames 0, 20, 40, 60, 80 of 95
  EXPECT_GT(j["summary"]["words"].get<int>(), 16);
  EXPECT_LE(j["summary"]["words"].get<int>(), 64);  // k^L
  EXPECT_GT(fs::file_size(out), 64u);
  const auto again = testing::run_command(command);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_THAT(again.err, HasSubstr("output exists"));
}

TEST(VocabCommand, BadDatasetExitsOneNamingIt) {
  testing::TempDir dir;
  const auto r = testing::run_command(fmt::format("{} vocab --datasets {} --out {}", kEdx,
                                                  (dir.path() / "nowhere").string(),
                                                  (dir.path() / "v.bin").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("nowhere"));
  EXPECT_FALSE(fs::exists(dir.path() / "v.bin"));
}

}  // namespace
}  // namespace edx
