// Bad values that used to be accepted silently (issue 21, class 6): each is now a one-line error
// naming the option, file or key, with a non-zero exit and no output created.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;

std::string edx() { return fmt::format("'{}'", built_binary("edx")); }

TEST(BadValue, OptionsNegativeSeedsAndEmptyPathsAreRefused) {
  const TempDir dir;
  const CommandResult seed =
      run_command(fmt::format("{} gen --scenario indoor_unknown --frames 2 --seed -1 --out '{}'",
                              edx(), (dir.path() / "g").string()));
  EXPECT_EQ(seed.exit_code, 2);
  EXPECT_EQ(seed.err, "edx: --seed: expected a non-negative integer, got '-1' (see edx --help)\n");
  EXPECT_FALSE(fs::exists(dir.path() / "g"));
  const CommandResult out = run_command(fmt::format(
      "{} simulate --config '{}/configs/edx_car.yaml' --trace '{}/tests/data/golden/golden_mix.db' "
      "--out ''",
      edx(), EDX_SOURCE_DIR, EDX_SOURCE_DIR));
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_EQ(out.err, "edx: --out: expected a path, got '' (see edx --help)\n");
}

TEST(BadValue, ATimelinePastTheTraceAndAKeyWrittenTwiceAreErrors) {
  const TempDir dir;
  const std::string trace = fmt::format("{}/tests/data/golden/golden_mix.db", EDX_SOURCE_DIR);
  const fs::path timeline = dir.path() / "tl.json";
  const CommandResult late = run_command(
      fmt::format("{} simulate --config '{}/configs/edx_car.yaml' --trace '{}' --timeline '{}' "
                  "--timeline-first 100000",
                  edx(), EDX_SOURCE_DIR, trace, timeline.string()));
  EXPECT_EQ(late.exit_code, 1);
  EXPECT_EQ(late.err, "edx: error: " + trace +
                          ": the timeline's first frame 100000 is past the trace's last (240 "
                          "frames)\n");
  EXPECT_FALSE(fs::exists(timeline));
  const fs::path config = dir.path() / "dup.yaml";
  std::ofstream(config) << "name: a\nbackend:\n  gemm_block: 4\n  gemm_block: 8\n";
  const CommandResult twice = run_command(
      fmt::format("{} simulate --config '{}' --trace '{}'", edx(), config.string(), trace));
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_EQ(twice.err, "edx: error: " + config.string() +
                           ":4: backend.gemm_block: written twice (also on "
                           "line 3)\n");
}

}  // namespace
}  // namespace edx::testing
