// TextTable splitting, comments and number parsing.
#include "workloads/datasets/text_table.hpp"

#include <gtest/gtest.h>

#include "tests/workloads/datasets/tiny_datasets.hpp"

namespace edx::datasets {
namespace {

TEST(TextTable, SplitsTrimsAndSkipsCommentsAndBlankLines) {
  testing::TempFolder folder("text_table");
  const auto file = folder.path() / "t.csv";
  testing::write_text(file, "#header,a,b\r\n1, 2.5 ,x\r\n\n  \n# comment\n4,,6\n");
  const TextTable table(file, FieldSeparator::kComma);
  ASSERT_EQ(table.rows().size(), 2u);
  EXPECT_EQ(table.rows()[0].line, 2u);
  EXPECT_EQ(table.rows()[0].fields, (std::vector<std::string>{"1", "2.5", "x"}));
  EXPECT_EQ(table.rows()[1].line, 6u);
  EXPECT_EQ(table.rows()[1].fields, (std::vector<std::string>{"4", "", "6"}));
  EXPECT_EQ(table.integer(table.rows()[0], 0, "a"), 1);
  EXPECT_DOUBLE_EQ(table.real(table.rows()[0], 1, "b"), 2.5);
  try {
    table.real(table.rows()[0], 2, "c");
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.string() + ":2: field 3 (c) must be a finite number, got 'x'");
  }
  EXPECT_THROW(table.require_field_count(table.rows()[1], 4), std::runtime_error);

  testing::write_text(file, "P0: 1 2\t3\n  7.5e-01   8  \n");
  const TextTable blanks(file, FieldSeparator::kWhitespace);
  EXPECT_EQ(blanks.rows()[0].fields, (std::vector<std::string>{"P0:", "1", "2", "3"}));
  EXPECT_EQ(blanks.rows()[1].fields, (std::vector<std::string>{"7.5e-01", "8"}));
}

TEST(TextTable, NumberParsingIsStrict) {
  double real = 0;
  std::int64_t integer = 0;
  EXPECT_TRUE(parse_real("-1.5e-3", real));
  EXPECT_DOUBLE_EQ(real, -1.5e-3);
  EXPECT_TRUE(parse_real("+2", real));
  for (const char* bad : {"", "1.0abc", "nan", "inf", "1,0", " 1"}) {
    EXPECT_FALSE(parse_real(bad, real)) << bad;
  }
  EXPECT_TRUE(parse_integer("1403715273262142976", integer));
  EXPECT_EQ(integer, 1403715273262142976);
  for (const char* bad : {"", "1.5", "1e9", "99999999999999999999", "12a"}) {
    EXPECT_FALSE(parse_integer(bad, integer)) << bad;
  }
}

TEST(TextTable, MissingFileIsNamed) {
  try {
    TextTable("/nonexistent/edx/data.csv", FieldSeparator::kComma);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/edx/data.csv: file not found");
  }
}

}  // namespace
}  // namespace edx::datasets
