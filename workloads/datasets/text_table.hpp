#pragma once
// Reading of the plain-text tables the datasets are made of (EuRoC CSV files, KITTI calib.txt,
// times.txt and pose files), with errors that name the file and the line.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace edx::datasets {

/// One data line of a text table: its 1-based line number in the file and its fields.
struct TableRow {
  std::size_t line = 0;
  std::vector<std::string> fields;
};

/// How a table's lines are split into fields.
enum class FieldSeparator {
  kComma,      ///< CSV: fields between commas, surrounding blanks trimmed (EuRoC)
  kWhitespace  ///< fields between runs of blanks or tabs (KITTI)
};

/// A text table read whole from a file. Blank lines and lines starting with '#' (EuRoC headers)
/// are skipped; a trailing '\r' is dropped. Every accessor that fails throws std::runtime_error
/// "<file>:<line>: <what was expected>".
class TextTable {
 public:
  /// Reads `file`; throws std::runtime_error naming it when it cannot be opened.
  TextTable(const std::filesystem::path& file, FieldSeparator separator);

  const std::filesystem::path& file() const { return file_; }
  const std::vector<TableRow>& rows() const { return rows_; }

  /// Throws unless `row` has exactly `count` fields.
  void require_field_count(const TableRow& row, std::size_t count) const;
  /// Field `column` (0-based) of `row` as an integer; `what` names the column in errors.
  std::int64_t integer(const TableRow& row, std::size_t column, std::string_view what) const;
  /// Field `column` (0-based) of `row` as a finite real number.
  double real(const TableRow& row, std::size_t column, std::string_view what) const;
  /// Throws "<file>:<line>: <message>".
  [[noreturn]] void fail(const TableRow& row, std::string_view message) const;

 private:
  std::filesystem::path file_;
  std::vector<TableRow> rows_;
};

/// Parses the whole of `text` as an integer / a finite real; false when it is not one.
bool parse_integer(std::string_view text, std::int64_t& value);
bool parse_real(std::string_view text, double& value);

}  // namespace edx::datasets
