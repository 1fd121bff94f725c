#include "common/config_fields.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace edx {
namespace {

/// Shortest text of a bound: 1000, 0.5, 1e+09.
std::string number_text(double v) { return fmt::format("{}", v); }

bool is_list(FieldKind kind) {
  return kind == FieldKind::kNumberList || kind == FieldKind::kTextList;
}

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
    case FieldKind::kNumberList:
      return "list of numbers";
    case FieldKind::kTextList:
      return "list of texts";
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
  if (b.multiple != 0) {
    text += fmt::format("{}multiple of {}", text.empty() ? "" : ", ", number_text(b.multiple));
  }
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

/// What the errors of `spec` say it accepts.
std::string expected_text(const FieldSpec& spec) {
  if (!spec.expected.empty()) return spec.expected;
  std::string text;
  const bool integer = spec.kind == FieldKind::kInteger;
  if (!spec.choices.empty()) {
    text = choices_text(spec.choices);
  } else if (spec.kind == FieldKind::kFlag) {
    text = "true or false";
  } else if (spec.kind == FieldKind::kText) {
    text = "a text value";
  } else if (spec.kind == FieldKind::kTextList) {
    text = "a list of texts";
  } else if (spec.kind == FieldKind::kNumberList) {
    const std::string range = range_text(spec.bounds, false);
    text = "a list of numbers";
    if (!range.empty()) {
      text += (range.front() == '[' || range.front() == '(' ? " in " : " ") + range;
    }
  } else {
    text = spec.bounds.describe(integer);
  }
  if (spec.unset) text += " or " + spec.unset->text;
  return text;
}

/// Whether one value of `spec`'s kind (a list's element for lists) is accepted.
bool accepts(const FieldSpec& spec, const FieldValue& element) {
  if (const auto* number = std::get_if<double>(&element);
      number && !spec.bounds.contains(*number)) {
    return false;
  }
  if (const auto* integer = std::get_if<std::int64_t>(&element);
      integer && !spec.bounds.contains(static_cast<double>(*integer))) {
    return false;
  }
  return spec.choices.empty() || std::find(spec.choices.begin(), spec.choices.end(),
                                           field_value_text(element)) != spec.choices.end();
}

/// The first element of `value` (itself when it is no list) that `spec` does not accept.
std::optional<FieldValue> refused_element(const FieldSpec& spec, const FieldValue& value) {
  if (std::holds_alternative<std::monostate>(value)) return std::nullopt;
  if (const auto* numbers = std::get_if<std::vector<double>>(&value)) {
    for (double v : *numbers) {
      if (!accepts(spec, v)) return FieldValue(v);
    }
    return std::nullopt;
  }
  if (const auto* texts = std::get_if<std::vector<std::string>>(&value)) {
    for (const std::string& v : *texts) {
      if (!accepts(spec, v)) return FieldValue(v);
    }
    return std::nullopt;
  }
  if (accepts(spec, value)) return std::nullopt;
  return value;
}

/// A key declared on the spot (link.preset, a section's `units`).
FieldSpec spec_of(const std::string& key, FieldKind kind, const Bounds& bounds,
                  const std::vector<std::string>& choices) {
  FieldSpec spec;
  spec.key = key;
  spec.kind = kind;
  spec.bounds = bounds;
  spec.choices = choices;
  return spec;
}

/// One scalar of `kind` (a list's element kind for lists) decoded from YAML.
std::optional<FieldValue> decode_scalar(const YAML::Node& node, FieldKind kind) {
  if (!node.IsScalar()) return std::nullopt;
  switch (kind) {
    case FieldKind::kFlag: {
      bool parsed = false;
      if (!YAML::convert<bool>::decode(node, parsed)) return std::nullopt;
      return parsed;
    }
    case FieldKind::kInteger: {
      std::int64_t parsed = 0;
      if (!YAML::convert<std::int64_t>::decode(node, parsed)) return std::nullopt;
      return parsed;
    }
    case FieldKind::kNumber:
    case FieldKind::kNumberList: {
      double parsed = 0;
      if (!YAML::convert<double>::decode(node, parsed)) return std::nullopt;
      return parsed;
    }
    case FieldKind::kText:
    case FieldKind::kTextList:
      return node.Scalar();
  }
  return std::nullopt;
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

Bounds Bounds::multiple_of(double step) const {
  Bounds b = *this;
  b.multiple = step;
  return b;
}

bool Bounds::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  if (odd && std::fmod(std::fabs(v), 2.0) != 1.0) return false;
  if (multiple != 0 && std::fmod(v, multiple) != 0) return false;
  return true;
}

std::string Bounds::describe(bool integer) const {
  const std::string what = odd             ? "an odd integer"
                           : multiple != 0 ? "a multiple of " + number_text(multiple)
                           : integer       ? "an integer"
                                           : "a number";
  Bounds plain = *this;
  plain.odd = false;
  plain.multiple = 0;
  const std::string range = range_text(plain, integer);
  if (range.empty()) return what;
  return range.front() == '[' || range.front() == '(' ? what + " in " + range : what + " " + range;
}

FieldValue read_field_value(const YamlFields& fields, const FieldSpec& spec,
                            const YAML::Node& node) {
  const auto refuse = [&](const std::string& got) {
    fields.fail(InputError::expected(spec.key, expected_text(spec), got));
  };
  if (spec.unset && (node.IsNull() || (node.IsScalar() && (node.Scalar() == "~" ||
                                                           node.Scalar() == spec.unset->text)))) {
    return std::monostate();
  }
  FieldValue value;
  if (is_list(spec.kind)) {
    if (!node.IsSequence()) refuse(YamlFields::described(node));
    std::vector<double> numbers;
    std::vector<std::string> texts;
    for (const YAML::Node& item : node) {
      const std::optional<FieldValue> element = decode_scalar(item, spec.kind);
      if (!element || !accepts(spec, *element)) refuse(YamlFields::described(item));
      if (spec.kind == FieldKind::kNumberList) {
        numbers.push_back(std::get<double>(*element));
      } else {
        texts.push_back(std::get<std::string>(*element));
      }
    }
    if (spec.kind == FieldKind::kNumberList) return numbers;
    return texts;
  }
  const std::optional<FieldValue> scalar = decode_scalar(node, spec.kind);
  if (!scalar || !accepts(spec, *scalar)) refuse(YamlFields::described(node));
  return *scalar;
}

FieldValue read_field_value(const YamlFields& fields, const std::string& key,
                            const YAML::Node& node, FieldKind kind, const Bounds& bounds,
                            const std::vector<std::string>& choices) {
  return read_field_value(fields, spec_of(key, kind, bounds, choices), node);
}

std::optional<InputError> field_value_problem(const FieldValue& value, const FieldSpec& spec) {
  const std::optional<FieldValue> refused = refused_element(spec, value);
  if (!refused) return std::nullopt;
  return InputError::expected(spec.key, expected_text(spec), field_value_text(*refused));
}

nlohmann::json field_value_json(const FieldValue& value, const FieldSpec& spec) {
  return std::visit(
      [&spec](const auto& v) -> nlohmann::json {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>) {
          return spec.unset ? spec.unset->json : nlohmann::json();  // an unset optional
        } else {
          return v;
        }
      },
      value);
}

std::string field_value_text(const FieldValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "(unset)";
        } else if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return v.empty() ? "(empty)" : v;
        } else if constexpr (std::is_same_v<T, std::vector<double>> ||
                             std::is_same_v<T, std::vector<std::string>>) {
          return fmt::format("[{}]", fmt::join(v, ", "));
        } else {
          return fmt::format("{}", v);
        }
      },
      value);
}

ReferenceRow reference_row(const std::string& section, const FieldSpec& spec,
                           const FieldValue& value) {
  ReferenceRow row;
  row.key = section.empty() ? spec.key : section + "." + spec.key;
  row.type = kind_name(spec.kind);
  row.unit = spec.unit;
  if (!spec.missing.empty()) {
    row.value = "(required)";
  } else if (std::holds_alternative<std::monostate>(value) && spec.unset) {
    row.value = spec.unset->text;
  } else {
    row.value = field_value_text(value);
  }
  if (!spec.expected.empty()) {
    row.accepted = spec.expected;
  } else if (!spec.choices.empty()) {
    row.accepted = choices_text(spec.choices);
  } else if (spec.kind != FieldKind::kFlag) {
    row.accepted = range_text(spec.bounds, spec.kind == FieldKind::kInteger);
  }
  if (spec.unset && spec.expected.empty() && !row.accepted.empty()) {
    row.accepted += " or " + spec.unset->text;
  }
  row.doc = spec.doc;
  return row;
}

ReferenceRow reference_row(const std::string& section, const std::string& key, FieldKind kind,
                           const std::string& unit, const FieldValue& value, const Bounds& bounds,
                           const std::vector<std::string>& choices, const std::string& doc) {
  FieldSpec spec = spec_of(key, kind, bounds, choices);
  spec.unit = unit;
  spec.doc = doc;
  return reference_row(section, spec, value);
}

void validate_at(const YamlFields& fields, const std::function<void()>& validate) {
  try {
    validate();
  } catch (const InputError& e) {
    if (e.place().known()) throw;
    // "section.key" (section possibly dotted: "link.dma.chunk_bytes"; a key below the map's own
    // prefix possibly too: "backend.units.gemm").
    const std::string& key = e.key();
    const std::string below = fields.prefix() + ".";
    const std::size_t dot = key.rfind('.');
    if (fields.prefix().empty() || dot == std::string::npos) fields.fail(e);
    fields.fail(
        e.with_key(key.starts_with(below) ? key.substr(below.size()) : key.substr(dot + 1)));
  }
}

void require_field(bool ok, const std::string& section, const std::string& key,
                   const std::string& expected, std::optional<std::string> got) {
  if (!ok) {
    throw InputError::expected(section.empty() ? key : section + "." + key, expected,
                               std::move(got));
  }
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
