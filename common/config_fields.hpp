#pragma once
// One field list per config struct (Timeloop's "specs as plain structs parsed from config"):
// every key of an input file's map (a platform section, a sweep spec, the paper targets, the
// host cost table) or of a set of options is declared once, with its member, unit, accepted
// values and a one-line description, and that one list drives
//   parse_fields   YAML -> struct, each value checked at its file:line as it is read,
//   check_fields   the same checks on a struct built in code (validate()),
//   fields_to_json struct -> JSON (results databases, `edx simulate --json`, trace meta),
//   reference_rows the reference of every key (`edx config --reference`, docs/CONFIG.md).
// Rules between fields (host_idle_w <= host_active_w) stay in each struct's validate(), which
// reports them with require_field. Every error is an edx::InputError.
//
// A field is a number, integer, flag or text member, an std::optional of one (optional_field),
// a list of numbers or texts, a value reached through accessors (accessor_field), or a field
// of a nested struct (nested_fields: key "random_walk.step_sigma_px", nested in JSON).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "common/input_error.hpp"
#include "common/yaml_fields.hpp"

namespace edx {

/// Accepted numbers: lo <= v (lo < v when lo_open), v <= hi (v < hi when hi_open), odd integers
/// only when `odd`, multiples of `multiple` only when it is not 0. Built as
/// Bounds::above(0).at_most(1000) = (0, 1000].
struct Bounds {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
  bool odd = false;
  double multiple = 0;

  static Bounds any() { return {}; }
  static Bounds at_least(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), false, false, false, 0};
  }
  static Bounds above(double lo) {
    return {lo, std::numeric_limits<double>::infinity(), true, false, false, 0};
  }
  Bounds at_most(double bound) const;
  Bounds below(double bound) const;
  Bounds odd_only() const;
  Bounds multiple_of(double step) const;

  bool contains(double value) const;
  /// "a number > 0", "an integer in [1, 256]", "an odd integer >= 3", "a multiple of 4 in [8,
  /// 16]".
  std::string describe(bool integer) const;
};

enum class FieldKind { kFlag, kInteger, kNumber, kText, kNumberList, kTextList };
/// A field's value as the generic code sees it; std::monostate: an optional field left unset.
using FieldValue = std::variant<std::monostate, bool, std::int64_t, double, std::string,
                                std::vector<double>, std::vector<std::string>>;

/// An optional field's "no value": the text that means it in a file ("default") and in the
/// reference, and its JSON (null, "from dataset").
struct Unset {
  std::string text;
  nlohmann::json json;
};

/// What a key is and accepts, whatever struct holds it.
struct FieldSpec {
  std::string key;
  FieldKind kind = FieldKind::kNumber;
  std::string unit;                  ///< "MHz", "bytes", "" for counts, flags and names
  std::string doc;                   ///< one line: what it is, and its source
  Bounds bounds;                     ///< numbers (each number of a list)
  std::vector<std::string> choices;  ///< the accepted values, as text (empty: any in bounds)
  /// What errors say the key accepts, when not generated from bounds and choices ("an integer
  /// from 1 to 10^6").
  std::string expected;
  /// The error when the key is absent from a map ("required"); empty: the key is optional.
  std::string missing;
  std::optional<Unset> unset;  ///< set for an optional field (an std::optional member)
};

/// One key of a config struct: its spec and how to read and write it in the struct.
template <class Config>
struct Field : FieldSpec {
  std::function<FieldValue(const Config&)> get;
  std::function<void(Config&, const FieldValue&)> set;

  /// The same field, its errors saying it accepts `text` ("an integer from 1 to 10^6").
  Field expects(std::string text) && {
    expected = std::move(text);
    return std::move(*this);
  }
  /// The same field, required in a file: `message` when it is absent ("required").
  Field required(std::string message = "required") && {
    missing = std::move(message);
    return std::move(*this);
  }
};

template <class Config>
using FieldList = std::vector<Field<Config>>;

namespace detail {

template <class T>
constexpr FieldKind field_kind() {
  if constexpr (std::is_same_v<T, bool>) {
    return FieldKind::kFlag;
  } else if constexpr (std::is_integral_v<T>) {
    return FieldKind::kInteger;
  } else if constexpr (std::is_floating_point_v<T>) {
    return FieldKind::kNumber;
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    return FieldKind::kNumberList;
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    return FieldKind::kTextList;
  } else {
    return FieldKind::kText;
  }
}

/// A member's value as a FieldValue, and back.
template <class T>
FieldValue to_field_value(const T& v) {
  if constexpr (std::is_same_v<T, bool>) {
    return v;
  } else if constexpr (std::is_integral_v<T>) {
    return static_cast<std::int64_t>(v);
  } else if constexpr (std::is_floating_point_v<T>) {
    return static_cast<double>(v);
  } else if constexpr (std::is_same_v<T, std::vector<double>> ||
                       std::is_same_v<T, std::vector<std::string>>) {
    return v;
  } else {
    return std::string(v);
  }
}

template <class T>
T from_field_value(const FieldValue& v) {
  if constexpr (std::is_same_v<T, bool>) {
    return std::get<bool>(v);
  } else if constexpr (std::is_integral_v<T>) {
    return static_cast<T>(std::get<std::int64_t>(v));
  } else if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(std::get<double>(v));
  } else if constexpr (std::is_same_v<T, std::vector<double>> ||
                       std::is_same_v<T, std::vector<std::string>>) {
    return std::get<T>(v);
  } else {
    return T(std::get<std::string>(v));
  }
}

/// An integer member cannot hold more than its type does (an int: INT_MAX).
template <class T>
Bounds within_type(Bounds bounds) {
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    bounds.lo = std::max(bounds.lo, static_cast<double>(std::numeric_limits<T>::min()));
    bounds.hi = std::min(bounds.hi, static_cast<double>(std::numeric_limits<T>::max()));
  }
  return bounds;
}

}  // namespace detail

/// A field read and written through `get` and `set` (a member that is no plain value, such as an
/// Eigen vector written as a list of numbers).
template <class Config>
Field<Config> accessor_field(std::string key, FieldKind kind,
                             std::function<FieldValue(const Config&)> get,
                             std::function<void(Config&, const FieldValue&)> set, std::string unit,
                             std::string doc, Bounds bounds = {}) {
  Field<Config> f;
  f.key = std::move(key);
  f.kind = kind;
  f.unit = std::move(unit);
  f.doc = std::move(doc);
  f.bounds = bounds;
  f.get = std::move(get);
  f.set = std::move(set);
  return f;
}

/// A field stored in member `member` of Config (double, an integer type, bool, std::string,
/// std::filesystem::path, std::vector<double>, std::vector<std::string>).
template <class Config, class T>
Field<Config> field(std::string key, T Config::*member, std::string unit, std::string doc,
                    Bounds bounds = {}) {
  return accessor_field<Config>(
      std::move(key), detail::field_kind<T>(),
      [member](const Config& c) { return detail::to_field_value(c.*member); },
      [member](Config& c, const FieldValue& v) { c.*member = detail::from_field_value<T>(v); },
      std::move(unit), std::move(doc), detail::within_type<T>(bounds));
}

/// A field stored in an std::optional member: `unset` when it holds nothing (in a file: ~, null
/// or unset.text).
template <class Config, class T>
Field<Config> optional_field(std::string key, std::optional<T> Config::*member, std::string unit,
                             std::string doc, Bounds bounds, Unset unset) {
  Field<Config> f = accessor_field<Config>(
      std::move(key), detail::field_kind<T>(),
      [member](const Config& c) -> FieldValue {
        return (c.*member) ? detail::to_field_value(*(c.*member)) : FieldValue();
      },
      [member](Config& c, const FieldValue& v) {
        if (std::holds_alternative<std::monostate>(v)) {
          (c.*member).reset();
        } else {
          c.*member = detail::from_field_value<T>(v);
        }
      },
      std::move(unit), std::move(doc), detail::within_type<T>(bounds));
  f.unset = std::move(unset);
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
  Field<Config> f = accessor_field<Config>(
      std::move(key), FieldKind::kText,
      [member, name](const Config& c) -> FieldValue { return std::string(name(c.*member)); },
      [member, parse](Config& c, const FieldValue& v) {
        c.*member = parse(std::get<std::string>(v));
      },
      "", std::move(doc));
  f.choices = std::move(choices);
  return f;
}

/// The fields of `inner`, a nested struct in `member` of Outer, as fields of Outer keyed
/// "prefix.key" (JSON: {"prefix": {"key": ...}}; errors and the reference: "prefix.key"); an
/// empty prefix keeps the inner keys as they are (a struct whose keys sit beside Outer's own).
template <class Outer, class Inner>
FieldList<Outer> nested_fields(const std::string& prefix, Inner Outer::*member,
                               const FieldList<Inner>& inner) {
  FieldList<Outer> list;
  for (const Field<Inner>& f : inner) {
    Field<Outer> nested;
    static_cast<FieldSpec&>(nested) = f;
    nested.key = prefix.empty() ? f.key : prefix + "." + f.key;
    nested.get = [member, get = f.get](const Outer& o) { return get(o.*member); };
    nested.set = [member, set = f.set](Outer& o, const FieldValue& v) { set(o.*member, v); };
    list.push_back(std::move(nested));
  }
  return list;
}

/// `lists` one after the other (a struct's own fields and its nested structs').
template <class Config>
FieldList<Config> joined(std::initializer_list<FieldList<Config>> lists) {
  FieldList<Config> all;
  for (const FieldList<Config>& list : lists) all.insert(all.end(), list.begin(), list.end());
  return all;
}

/// The keys of `list`, in order ("expected one of: ..." of unknown keys).
template <class Config>
std::vector<std::string> field_keys(const FieldList<Config>& list) {
  std::vector<std::string> keys;
  for (const Field<Config>& f : list) keys.push_back(f.key);
  return keys;
}

/// Reads `node` (YAML) as a value of `spec`; otherwise fails at the key's line: "file:12:
/// frontend.clock_mhz: expected a number in (0, 1000], got 'fast'".
FieldValue read_field_value(const YamlFields& fields, const FieldSpec& spec,
                            const YAML::Node& node);
/// The same for a key declared on the spot.
FieldValue read_field_value(const YamlFields& fields, const std::string& key,
                            const YAML::Node& node, FieldKind kind, const Bounds& bounds,
                            const std::vector<std::string>& choices);
/// The error of `value` for `spec` (key: spec.key), if it is not accepted.
std::optional<InputError> field_value_problem(const FieldValue& value, const FieldSpec& spec);
/// `value` as JSON (an unset optional: its Unset json).
nlohmann::json field_value_json(const FieldValue& value, const FieldSpec& spec);
/// `value` as reference text ("150", "true", "on_chip_double", "(empty)", "[1, 2]").
std::string field_value_text(const FieldValue& value);

/// Reads every field of `list` present in the map of `fields` into `config`; a required field
/// that is absent is an error, and so is a value a field's setter refuses (an InputError it
/// throws, such as a malformed "WxH").
template <class Config>
void parse_fields(YamlFields& fields, Config& config, const FieldList<Config>& list) {
  for (const Field<Config>& f : list) {
    const YAML::Node node = fields.take(f.key);
    if (!node) {
      if (!f.missing.empty()) fields.fail(f.key, f.missing);
      continue;
    }
    const FieldValue value = read_field_value(fields, f, node);
    try {
      f.set(config, value);
    } catch (const InputError& e) {
      fields.fail(e.with_key(f.key));
    }
  }
}

/// Throws InputError "section.key: expected ..., got ..." for the first field of `config`
/// outside what it accepts (`section` "": the key alone).
template <class Config>
void check_fields(const Config& config, const std::string& section, const FieldList<Config>& list) {
  for (const Field<Config>& f : list) {
    if (auto problem = field_value_problem(f.get(config), f)) {
      throw problem->with_key(section.empty() ? f.key : section + "." + f.key);
    }
  }
}

/// Every field as JSON; a dotted key as nested objects ("random_walk.step_sigma_px").
template <class Config>
nlohmann::json fields_to_json(const Config& config, const FieldList<Config>& list) {
  nlohmann::json j = nlohmann::json::object();
  for (const Field<Config>& f : list) {
    std::string pointer = "/" + f.key;
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    j[nlohmann::json::json_pointer(pointer)] = field_value_json(f.get(config), f);
  }
  return j;
}

/// One key of the reference (docs/CONFIG.md).
struct ReferenceRow {
  std::string key;  ///< dotted: "frontend.clock_mhz"
  /// The heading of its table (Markdown) when it is not the key's section: a component kind's
  /// keys ("`backend.units.<name>` of kind `systolic_array`: ...").
  std::string group;
  std::string type;  ///< number, integer, true/false, text, list of numbers, list of texts
  std::string unit;
  std::string value;     ///< the default ("(required)" for a required key)
  std::string accepted;  ///< "> 0", "[1, 256]", "on_chip_double, dram"
  std::string doc;
};

/// The reference row of `spec` under `section`, its default `value`.
ReferenceRow reference_row(const std::string& section, const FieldSpec& spec,
                           const FieldValue& value);
/// The same for a key declared on the spot.
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
    rows.push_back(reference_row(section, f, f.get(defaults)));
    rows.back().group = group;
  }
  return rows;
}

/// Runs `validate` (a struct's validate(): field checks and rules between fields) and reports
/// its InputError at the key's line in `fields` (the one place that maps a validation error back
/// to the file). Its key is "section.key": the part below the map's prefix names the key
/// ("link.dma.chunk_bytes" in `link.dma`), else its last part ("systolic_array.block" in
/// `backend.units.gemm`).
void validate_at(const YamlFields& fields, const std::function<void()>& validate);

/// Throws InputError "section.key: expected <expected>[, got '<got>']" unless `ok` (rules
/// between fields in validate()).
void require_field(bool ok, const std::string& section, const std::string& key,
                   const std::string& expected, std::optional<std::string> got = std::nullopt);

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
