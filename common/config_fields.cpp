#include "common/config_fields.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edx {
namespace {

/// Shortest text of a bound: 1000, 0.5, 1e+09.
std::string number_text(double v) { return fmt::format("{}", v); }

std::string kind_name(FieldKind kind) {
  switch (kind) {
    case FieldKind::kFlag:
      return "true/false";
    case FieldKind::kInteger:
      return "integer";
    case FieldKind::kNumber:
      return "number";
    case FieldKind::kText:
      return "text";
    case FieldKind::kTextList:
      return "list of text";
  }
  return "";
}

/// The accepted range as "> 0", "[1, 256]", ">= 3, odd" (empty: anything of its kind).
std::string range_text(const Bounds& b, bool integer) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // The limits an int member adds on its own are not worth stating.
  const bool has_lo = b.lo > -kInf && !(integer && b.lo <= std::numeric_limits<int>::min());
  const bool has_hi = b.hi < kInf && !(integer && b.hi >= std::numeric_limits<int>::max());
  std::string text;
  if (has_lo && has_hi) {
    text = fmt::format("{}{}, {}{}", b.lo_open ? "(" : "[", number_text(b.lo), number_text(b.hi),
                       b.hi_open ? ")" : "]");
  } else if (has_lo) {
    text = fmt::format("{} {}", b.lo_open ? ">" : ">=", number_text(b.lo));
  } else if (has_hi) {
    text = fmt::format("{} {}", b.hi_open ? "<" : "<=", number_text(b.hi));
  }
  if (b.odd) text += text.empty() ? "odd" : ", odd";
  return text;
}

std::string choices_text(const std::vector<std::string>& choices) {
  if (choices.size() == 1) return choices.front();
  std::string text;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    text += i == 0 ? "" : (i + 1 == choices.size() ? " or " : ", ");
    text += choices[i];
  }
  return text;
}

std::string expected_text(FieldKind kind, const Bounds& bounds,
                          const std::vector<std::string>& choices) {
  switch (kind) {
    case FieldKind::kFlag:
      return "true or false";
    case FieldKind::kText:
      return choices.empty() ? "a text value" : choices_text(choices);
    case FieldKind::kTextList:
      return choices.empty() ? "a list of text values" : "a list of " + choices_text(choices);
    case FieldKind::kInteger:
    case FieldKind::kNumber:
      return choices.empty() ? bounds.describe(kind == FieldKind::kInteger) : choices_text(choices);
  }
  return "";
}

}  // namespace

Bounds Bounds::at_most(double bound) const {
  Bounds b = *this;
  b.hi = bound;
  b.hi_open = false;
  return b;
}

Bounds Bounds::below(double bound) const {
  Bounds b = *this;
  b.hi = bound;
  b.hi_open = true;
  return b;
}

Bounds Bounds::odd_only() const {
  Bounds b = *this;
  b.odd = true;
  return b;
}

bool Bounds::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  if (odd && std::fmod(std::fabs(v), 2.0) != 1.0) return false;
  return true;
}

std::string Bounds::describe(bool integer) const {
  const std::string what = odd ? "an odd integer" : (integer ? "an integer" : "a number");
  Bounds plain = *this;
  plain.odd = false;
  const std::string range = range_text(plain, integer);
  if (range.empty()) return what;
  return range.front() == '[' || range.front() == '(' ? what + " in " + range : what + " " + range;
}

FieldValue read_field_value(const YamlFields& fields, const std::string& key,
                            const YAML::Node& node, FieldKind kind, const Bounds& bounds,
                            const std::vector<std::string>& choices) {
  const auto refuse = [&] {
    fields.fail(key, fmt::format("expected {}, got '{}'", expected_text(kind, bounds, choices),
                                 YamlFields::described(node)));
  };
  if (kind == FieldKind::kTextList) {
    // [a, b, c]: each a text value, each one of `choices` when there are some.
    if (!node.IsSequence()) refuse();
    std::vector<std::string> items;
    for (const YAML::Node& item : node) {
      if (!item.IsScalar()) refuse();
      if (!choices.empty() &&
          std::find(choices.begin(), choices.end(), item.Scalar()) == choices.end()) {
        fields.fail(key, fmt::format("expected a list of {}, got '{}' in it", choices_text(choices),
                                     item.Scalar()));
      }
      items.push_back(item.Scalar());
    }
    return items;
  }
  if (!node.IsScalar()) refuse();
  FieldValue value;
  switch (kind) {
    case FieldKind::kFlag: {
      bool parsed = false;
      if (!YAML::convert<bool>::decode(node, parsed)) refuse();
      value = parsed;
      break;
    }
    case FieldKind::kInteger: {
      std::int64_t parsed = 0;
      if (!YAML::convert<std::int64_t>::decode(node, parsed)) refuse();
      value = parsed;
      break;
    }
    case FieldKind::kNumber: {
      double parsed = 0;
      if (!YAML::convert<double>::decode(node, parsed)) refuse();
      value = parsed;
      break;
    }
    case FieldKind::kText:
    case FieldKind::kTextList:
      value = node.Scalar();
      break;
  }
  if (field_value_problem(value, kind, bounds, choices)) refuse();
  return value;
}

std::optional<std::string> field_value_problem(const FieldValue& value, FieldKind kind,
                                               const Bounds& bounds,
                                               const std::vector<std::string>& choices) {
  bool ok = true;
  switch (kind) {
    case FieldKind::kFlag:
      break;
    case FieldKind::kInteger:
      ok = bounds.contains(static_cast<double>(std::get<std::int64_t>(value)));
      break;
    case FieldKind::kNumber:
      ok = bounds.contains(std::get<double>(value));
      break;
    case FieldKind::kText:
      break;
    case FieldKind::kTextList:
      for (const std::string& item : std::get<std::vector<std::string>>(value)) {
        if (!choices.empty() && std::find(choices.begin(), choices.end(), item) == choices.end()) {
          return fmt::format("expected a list of {}, got '{}' in it", choices_text(choices), item);
        }
      }
      return std::nullopt;
  }
  if (ok && !choices.empty()) {
    ok = std::find(choices.begin(), choices.end(), field_value_text(value)) != choices.end();
  }
  if (ok) return std::nullopt;
  return fmt::format("expected {}, got '{}'", expected_text(kind, bounds, choices),
                     field_value_text(value));
}

nlohmann::json field_value_json(const FieldValue& value) {
  return std::visit([](const auto& v) { return nlohmann::json(v); }, value);
}

std::string field_value_text(const FieldValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return v.empty() ? "(empty)" : v;
        } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          return v.empty() ? "(none)" : fmt::format("[{}]", fmt::join(v, ", "));
        } else {
          return fmt::format("{}", v);
        }
      },
      value);
}

ReferenceRow reference_row(const std::string& section, const std::string& key, FieldKind kind,
                           const std::string& unit, const FieldValue& value, const Bounds& bounds,
                           const std::vector<std::string>& choices, const std::string& doc) {
  ReferenceRow row;
  row.key = section.empty() ? key : section + "." + key;
  row.type = kind_name(kind);
  row.unit = unit;
  row.value = field_value_text(value);
  if (!choices.empty()) {
    row.accepted = choices_text(choices);
  } else if (kind != FieldKind::kFlag) {
    row.accepted = range_text(bounds, kind == FieldKind::kInteger);
  }
  row.doc = doc;
  return row;
}

void validate_at(const YamlFields& fields, const std::function<void()>& validate) {
  try {
    validate();
  } catch (const std::runtime_error& e) {
    // "section.key: message" (section possibly dotted: "link.dma.chunk_bytes"; a key below the
    // map's own prefix possibly too: "backend.units.gemm").
    const std::string message = e.what();
    const std::size_t colon = message.find(": ");
    const std::string path = message.substr(0, colon);
    const std::size_t dot = path.rfind('.');
    if (colon == std::string::npos || dot == std::string::npos) throw;
    const std::string below = fields.prefix() + ".";
    fields.fail(path.starts_with(below) ? path.substr(below.size()) : path.substr(dot + 1),
                message.substr(colon + 2));
  }
}

void require_field(bool ok, const std::string& section, const std::string& key,
                   const std::string& expected) {
  if (!ok) throw std::runtime_error(fmt::format("{}.{}: expected {}", section, key, expected));
}

std::string render_reference(const std::vector<ReferenceRow>& rows) {
  // Markdown cells: a '|' would end the cell.
  const auto cell = [](std::string text) {
    for (std::size_t at = text.find('|'); at != std::string::npos; at = text.find('|', at + 2)) {
      text.replace(at, 1, "\\|");
    }
    return text;
  };
  std::string out;
  std::string section = "\x01";
  for (const ReferenceRow& row : rows) {
    const std::size_t dot = row.key.rfind('.');
    const std::string key_section = dot == std::string::npos ? "" : row.key.substr(0, dot);
    const std::string row_section = row.group.empty() ? key_section : row.group;
    if (row_section != section) {
      section = row_section;
      out += section.empty()      ? std::string("\n## Top level\n\n")
             : !row.group.empty() ? fmt::format("\n## {}\n\n", section)
                                  : fmt::format("\n## `{}:`\n\n", section);
      out += "| key | type | unit | default | accepted | description |\n";
      out += "|---|---|---|---|---|---|\n";
    }
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", cell(row.key), row.type,
                       cell(row.unit), cell(row.value), cell(row.accepted), cell(row.doc));
  }
  return out;
}

}  // namespace edx
