// Installing where it runs (issue 20): `cmake --install` of this build into a scratch prefix,
// then the installed edx, which must read its files (paper targets, configs, sweeps) from
// <prefix>/share/edx, found from its own location (common/resources.hpp), never from the
// source tree; and the same after the whole prefix is moved elsewhere.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace edx::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// Runs `command` in `dir` without EDX_DATA_DIR (the data folder is the binary's own).
CommandResult run_in(const fs::path& dir, const std::string& command) {
  return run_command(fmt::format("cd '{}' && env -u EDX_DATA_DIR {}", dir.string(), command));
}

TEST(Install, TheInstalledEdxRunsOnItsOwnFilesAndMovesWithItsPrefix) {
  const TempDir dir;
  const fs::path prefix = dir.path() / "prefix";
  const CommandResult install = run_command(fmt::format(
      "'{}' --install '{}' --prefix '{}'", EDX_CMAKE_COMMAND, EDX_BUILD_DIR, prefix.string()));
  ASSERT_EQ(install.exit_code, 0) << install.out << install.err;

  // What is installed: the command and its files, no tests or benchmarks.
  const fs::path data = prefix / "share" / "edx";
  for (const char* file :
       {"configs/edx_car.yaml", "configs/edx_drone.yaml", "sweeps/gemm_block.yaml",
        "sweeps/link_bandwidth.yaml", "reports/paper_targets.yaml", "docs/MODEL.md"}) {
    EXPECT_TRUE(fs::is_regular_file(data / file)) << file;
  }
  std::vector<std::string> binaries = entries(prefix / "bin");
  EXPECT_EQ(binaries, std::vector<std::string>{"edx"});

  // It names its data folder; a move of the whole prefix takes it along.
  const fs::path moved = dir.path() / "elsewhere";
  fs::rename(prefix, moved);
  const std::string edx = (moved / "bin" / "edx").string();
  const CommandResult version = run_in(dir.path(), edx + " --version");
  ASSERT_EQ(version.exit_code, 0) << version.err;
  EXPECT_THAT(version.out, HasSubstr(fmt::format("data: {} (installed beside {})",
                                                 (moved / "share" / "edx").string(), edx)));

  // The paper check with the installed targets and config, as the build's edx does it.
  fs::copy_file(fs::path(EDX_SOURCE_DIR) / "tests" / "data" / "golden" / "golden_mix.db",
                dir.path() / "golden_mix.db");
  const std::string check_args =
      fmt::format("check --config '{}' --trace golden_mix.db --json",
                  (moved / "share" / "edx" / "configs" / "edx_car.yaml").string());
  const CommandResult installed_check = run_in(dir.path(), edx + " " + check_args);
  const CommandResult built_check = run_in(dir.path(), built_binary("edx") + " " + check_args);
  EXPECT_EQ(installed_check.exit_code, built_check.exit_code) << installed_check.err;
  EXPECT_EQ(installed_check.out, built_check.out);
  EXPECT_THAT(installed_check.out, HasSubstr("\"passed\""));

  // A sweep spec of the install finds its base config (../configs/) inside the install.
  const CommandResult sweep =
      run_in(dir.path(),
             fmt::format("{} sweep '{}' --trace golden_mix.db --db sweep.db -j 2 --json", edx,
                         (moved / "share" / "edx" / "sweeps" / "link_bandwidth.yaml").string()));
  EXPECT_EQ(sweep.exit_code, 0) << sweep.err;

  // Without its targets file the installed edx says so, naming the installed path: it does not
  // fall back to the source tree.
  fs::remove(moved / "share" / "edx" / "reports" / "paper_targets.yaml");
  const CommandResult missing = run_in(dir.path(), edx + " " + check_args);
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.err,
              HasSubstr((moved / "share" / "edx" / "reports" / "paper_targets.yaml").string()));
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  EXPECT_TRUE(missing.out.empty());
}

}  // namespace
}  // namespace edx::testing
