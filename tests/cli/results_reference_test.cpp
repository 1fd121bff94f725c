// `edx export --reference`: the reference of every results table and column is docs/RESULTS.md
// (checked current here, so CI fails when a table changes without it).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/run_command.hpp"

namespace {

using edx::testing::built_binary;
using edx::testing::run_command;
using ::testing::HasSubstr;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ResultsReference, IsTheCheckedInResultsMd) {
  const auto result = run_command(built_binary("edx") + " export --reference");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(result.out == read_file(std::string(EDX_SOURCE_DIR) + "/docs/RESULTS.md"))
      << "docs/RESULTS.md is stale: run `./build/bin/edx export --reference > docs/RESULTS.md`";
  EXPECT_THAT(result.out, HasSubstr("| `spill_bytes` | INTEGER | bytes |"));
}

TEST(ResultsReference, TakesNothingElse) {
  const auto result = run_command(built_binary("edx") + " export x.db --reference");
  EXPECT_EQ(result.exit_code, 2);
}

}  // namespace
