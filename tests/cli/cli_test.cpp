// End-to-end checks of the edx command's skeleton: version, help, and exit codes of bad
// command lines (one line on stderr, exit 2).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/support/run_command.hpp"

namespace {

using edx::testing::built_binary;
using edx::testing::run_command;
using ::testing::HasSubstr;
using ::testing::StartsWith;

long line_count(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

TEST(EdxCommand, VersionPrintsNameAndExitsZero) {
  const auto result = run_command(built_binary("edx") + " --version");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_THAT(result.out, StartsWith("edx 0."));
}

TEST(EdxCommand, HelpListsSubcommands) {
  const auto result = run_command(built_binary("edx") + " --help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_THAT(result.out, HasSubstr("eval"));
  EXPECT_THAT(result.out, HasSubstr("gen"));
}

TEST(EdxCommand, UnknownSubcommandIsOneLineErrorWithExitTwo) {
  const auto result = run_command(built_binary("edx") + " frobnicate");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
  EXPECT_THAT(result.err, HasSubstr("frobnicate"));
  EXPECT_TRUE(result.out.empty());
}

TEST(EdxCommand, UnknownFlagIsOneLineErrorWithExitTwo) {
  const auto result = run_command(built_binary("edx") + " --no-such-flag");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
  EXPECT_THAT(result.err, HasSubstr("--no-such-flag"));
}

TEST(EdxCommand, MissingSubcommandIsAnError) {
  const auto result = run_command(built_binary("edx"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(line_count(result.err), 1) << result.err;
}

}  // namespace
