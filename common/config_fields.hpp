#pragma once
// One field list per config struct (Timeloop's "specs as plain structs parsed from config"):
// every key of a platform section is declared once, with its member, unit, accepted values and
// a one-line description, and that one list drives
//   parse_fields   YAML -> struct, each value checked at its file:line as it is read,
//   check_fields   the same checks on a struct built in code (validate()),
//   fields_to_json struct -> JSON (results databases, `edx simulate --json`),
//   reference_rows the reference of every key (`edx config --reference`, docs/CONFIG.md).
// Rules between fields (a host's idle_w <= active_w) stay in each struct's validate().
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "common/yaml_fields.hpp"

namespace edx {

/// Accepted numbers: lo <= v (lo < v when lo_open), v <= hi (v < hi when hi_open), and odd
/// integers only when `odd`. Built as Bounds::above(0).at_most(1000) = (0, 1000].
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  bool odd = false;

  static Bounds any() { return {}; }
  static Bounds at_least(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), false, false, false};
  }
  static Bounds above(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), true, false, false};
  }
  Bounds at_most(double bound) const;
  Bounds below(double bound) const;
  Bounds odd_only() const;

  bool contains(double value) const;
  /// "a number > 0", "an integer in [1, 256]", "an odd integer >= 3".
  std::string describe(bool integer) const;
};

enum class FieldKind { kFlag, kInteger, kNumber, kText, kTextList };
/// A field's value as the generic code sees it.
using FieldValue = std::variant<bool, std::int64_t, double, std::string, std::vector<std::string>>;

/// One key of a config section: how to read and write it in the struct, and what it accepts.
template <class Config>
struct Field {
  std::string key;
  FieldKind kind = FieldKind::kNumber;
  std::function<FieldValue(const Config&)> get;
  std::function<void(Config&, const FieldValue&)> set;
  std::string unit;                  ///< "MHz", "bytes", "" for counts, flags and names
  std::string doc;                   ///< one line: what it is, and its source
  Bounds bounds;                     ///< numbers
  std::vector<std::string> choices;  ///< the accepted values, as text (empty: any in bounds)
};

/// A field stored in member `member` of Config (double, int, std::int64_t, bool, std::string).
template <class Config, class T>
Field<Config> field(std::string key, T Config::*member, std::string unit, std::string doc,
                    Bounds bounds = {}) {
  Field<Config> f;
  f.key = std::move(key);
  f.unit = std::move(unit);
  f.doc = std::move(doc);
  f.bounds = bounds;
  f.get = [member](const Config& c) -> FieldValue {
    if constexpr (std::is_same_v<T, bool>) {
      return c.*member;
    } else if constexpr (std::is_integral_v<T>) {
      return static_cast<std::int64_t>(c.*member);
    } else if constexpr (std::is_floating_point_v<T>) {
      return static_cast<double>(c.*member);
    } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
      return c.*member;
    } else {
      return std::string(c.*member);
    }
  };
  f.set = [member](Config& c, const FieldValue& v) {
    if constexpr (std::is_same_v<T, bool>) {
      c.*member = std::get<bool>(v);
    } else if constexpr (std::is_integral_v<T>) {
      c.*member = static_cast<T>(std::get<std::int64_t>(v));
    } else if constexpr (std::is_floating_point_v<T>) {
      c.*member = std::get<double>(v);
    } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
      c.*member = std::get<std::vector<std::string>>(v);
    } else {
      c.*member = std::get<std::string>(v);
    }
  };
  if constexpr (std::is_same_v<T, bool>) {
    f.kind = FieldKind::kFlag;
  } else if constexpr (std::is_integral_v<T>) {
    f.kind = FieldKind::kInteger;
    // An int member cannot hold more than INT_MAX.
    f.bounds.lo = std::max(f.bounds.lo, static_cast<double>(std::numeric_limits<T>::min()));
    f.bounds.hi = std::min(f.bounds.hi, static_cast<double>(std::numeric_limits<T>::max()));
  } else if constexpr (std::is_floating_point_v<T>) {
    f.kind = FieldKind::kNumber;
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    f.kind = FieldKind::kTextList;  // a YAML list of text values, each one of `choices`
  } else {
    f.kind = FieldKind::kText;
  }
  return f;
}

/// A field with a fixed set of `choices` (as text: "on_chip_double", "8"), stored in `member`.
template <class Config, class T>
Field<Config> choice_field(std::string key, T Config::*member, std::string unit,
                           std::vector<std::string> choices, std::string doc) {
  Field<Config> f = field(std::move(key), member, std::move(unit), std::move(doc));
  f.choices = std::move(choices);
  return f;
}

/// A text field with a fixed set of `choices` stored as an enum: `name` gives the text of a
/// value, `parse` the value of a text (called with one of `choices` only).
template <class Config, class Enum, class Name, class Parse>
Field<Config> enum_field(std::string key, Enum Config::*member, std::vector<std::string> choices,
                         Name name, Parse parse, std::string doc) {
  Field<Config> f;
  f.key = std::move(key);
  f.kind = FieldKind::kText;
  f.doc = std::move(doc);
  f.choices = std::move(choices);
  f.get = [member, name](const Config& c) -> FieldValue { return std::string(name(c.*member)); };
  f.set = [member, parse](Config& c, const FieldValue& v) {
    c.*member = parse(std::get<std::string>(v));
  };
  return f;
}

template <class Config>
using FieldList = std::vector<Field<Config>>;

/// Reads `node` (YAML text) as a value of `kind` accepted by `bounds` / `choices`; otherwise
/// fails at the key's line: "file:12: frontend.clock_mhz: expected a number in (0, 1000], got
/// 'fast'".
FieldValue read_field_value(const YamlFields& fields, const std::string& key,
                            const YAML::Node& node, FieldKind kind, const Bounds& bounds,
                            const std::vector<std::string>& choices);
/// The first problem of `value` for a field of `kind` ("expected ..., got ..."), if any.
std::optional<std::string> field_value_problem(const FieldValue& value, FieldKind kind,
                                               const Bounds& bounds,
                                               const std::vector<std::string>& choices);
/// `value` as JSON.
nlohmann::json field_value_json(const FieldValue& value);
/// `value` as reference text ("150", "true", "on_chip_double", "(empty)").
std::string field_value_text(const FieldValue& value);

/// Reads every field of `list` present in the map of `fields` into `config`.
template <class Config>
void parse_fields(YamlFields& fields, Config& config, const FieldList<Config>& list) {
  for (const Field<Config>& f : list) {
    const YAML::Node node = fields.take(f.key);
    if (node) f.set(config, read_field_value(fields, f.key, node, f.kind, f.bounds, f.choices));
  }
}

/// Throws std::runtime_error "section.key: expected ..., got ..." for the first field of
/// `config` outside what it accepts.
template <class Config>
void check_fields(const Config& config, const std::string& section, const FieldList<Config>& list) {
  for (const Field<Config>& f : list) {
    if (auto problem = field_value_problem(f.get(config), f.kind, f.bounds, f.choices)) {
      throw std::runtime_error(section + "." + f.key + ": " + *problem);
    }
  }
}

template <class Config>
nlohmann::json fields_to_json(const Config& config, const FieldList<Config>& list) {
  nlohmann::json j = nlohmann::json::object();
  for (const Field<Config>& f : list) j[f.key] = field_value_json(f.get(config));
  return j;
}

/// One key of the reference (docs/CONFIG.md).
struct ReferenceRow {
  std::string key;  ///< dotted: "frontend.clock_mhz"
  /// The heading of its table (Markdown) when it is not the key's section: a component kind's
  /// keys ("`backend.units.<name>` of kind `systolic_array`: ...").
  std::string group;
  std::string type;  ///< number, integer, true/false, text
  std::string unit;
  std::string value;     ///< the default
  std::string accepted;  ///< "> 0", "[1, 256]", "on_chip_double, dram"
  std::string doc;
};

ReferenceRow reference_row(const std::string& section, const std::string& key, FieldKind kind,
                           const std::string& unit, const FieldValue& value, const Bounds& bounds,
                           const std::vector<std::string>& choices, const std::string& doc);

/// The reference rows of `list` under `section`, defaults from `defaults`, in a table headed
/// `group` (empty: the section).
template <class Config>
std::vector<ReferenceRow> reference_rows(const std::string& section, const FieldList<Config>& list,
                                         const Config& defaults = Config{},
                                         const std::string& group = {}) {
  std::vector<ReferenceRow> rows;
  for (const Field<Config>& f : list) {
    rows.push_back(
        reference_row(section, f.key, f.kind, f.unit, f.get(defaults), f.bounds, f.choices, f.doc));
    rows.back().group = group;
  }
  return rows;
}

/// Runs `validate` (a struct's validate(): field checks and rules between fields) and reports
/// its "section.key: message" error at the key's line in `fields` (the one place that maps a
/// validation error back to the file).
void validate_at(const YamlFields& fields, const std::function<void()>& validate);

/// "section.key: expected <expected>" unless `ok` (rules between fields in validate()).
void require_field(bool ok, const std::string& section, const std::string& key,
                   const std::string& expected);

/// A `section:` map of a platform file read into a Config: its defaults, then every key present
/// (checked at its line), unknown keys refused, then Config::validate() (the rules between
/// fields) reported at the offending key's line. Config provides fields() and validate().
template <class Config>
Config parse_section(const YAML::Node& node, const std::string& where, const std::string& section,
                     Config config = Config{}) {
  YamlFields fields(node, where, section);
  parse_fields(fields, config, Config::fields());
  fields.finish();
  validate_at(fields, [&config] { config.validate(); });
  return config;
}

/// Markdown tables, one per section, of `rows` (grouped by the key's section or their group, in
/// order).
std::string render_reference(const std::vector<ReferenceRow>& rows);

}  // namespace edx
