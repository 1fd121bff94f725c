#include "workloads/datasets/text_table.hpp"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace edx::datasets {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> split(std::string_view line, FieldSeparator separator) {
  std::vector<std::string> fields;
  if (separator == FieldSeparator::kComma) {
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      fields.emplace_back(trim(line.substr(start, comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
  } else {
    std::size_t start = line.find_first_not_of(" \t");
    while (start != std::string_view::npos) {
      const auto end = line.find_first_of(" \t", start);
      fields.emplace_back(line.substr(start, end - start));
      start = line.find_first_not_of(" \t", end);
    }
  }
  return fields;
}

}  // namespace

bool parse_integer(std::string_view text, std::int64_t& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  return result.ec == std::errc{} && result.ptr == text.data() + text.size() && !text.empty();
}

bool parse_real(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  return result.ec == std::errc{} && result.ptr == text.data() + text.size() && !text.empty() &&
         std::isfinite(value);
}

TextTable::TextTable(const std::filesystem::path& file, FieldSeparator separator) : file_(file) {
  if (!std::filesystem::is_regular_file(file)) {
    throw std::runtime_error(fmt::format("{}: file not found", file.string()));
  }
  std::ifstream stream(file);
  if (!stream) throw std::runtime_error(fmt::format("{}: cannot open file", file.string()));
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    rows_.push_back({line_number, split(content, separator)});
  }
  if (stream.bad()) throw std::runtime_error(fmt::format("{}: read error", file.string()));
}

void TextTable::fail(const TableRow& row, std::string_view message) const {
  throw std::runtime_error(fmt::format("{}:{}: {}", file_.string(), row.line, message));
}

void TextTable::require_field_count(const TableRow& row, std::size_t count) const {
  if (row.fields.size() != count) {
    fail(row, fmt::format("expected {} fields, got {}", count, row.fields.size()));
  }
}

std::int64_t TextTable::integer(const TableRow& row, std::size_t column,
                                std::string_view what) const {
  std::int64_t value = 0;
  if (column >= row.fields.size() || !parse_integer(row.fields[column], value)) {
    fail(row, fmt::format("field {} ({}) must be an integer, got '{}'", column + 1, what,
                          column < row.fields.size() ? row.fields[column] : ""));
  }
  return value;
}

double TextTable::real(const TableRow& row, std::size_t column, std::string_view what) const {
  double value = 0;
  if (column >= row.fields.size() || !parse_real(row.fields[column], value)) {
    fail(row, fmt::format("field {} ({}) must be a finite number, got '{}'", column + 1, what,
                          column < row.fields.size() ? row.fields[column] : ""));
  }
  return value;
}

}  // namespace edx::datasets
