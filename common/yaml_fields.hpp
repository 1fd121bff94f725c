#pragma once
// One YAML map of an input file, read key by key (config_fields.hpp's parse_fields), with errors
// that name the file, line and key (edx::InputError): "car.yaml:12: frontend.clock_mhz: expected
// a number in (0, 1000], got 'fast'". Unknown keys are errors too (finish(): the keys never
// taken).
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/input_error.hpp"

namespace edx {

/// The text of the input file `path`; InputError "path: cannot read the <what>" when it cannot
/// be read, "path: is a directory (expected a <what>)" for a folder.
std::string read_input_file(const std::filesystem::path& path, const std::string& what);

/// Input limits of every YAML document edx reads (docs/RELIABILITY.md, "Input limits"). An
/// alias stands for its anchored node wherever it is written, so nested anchors ("a YAML alias
/// bomb") make a few lines stand for 10^9 nodes; every reader walks the expanded document.
/// Real inputs are far below: the largest platform has about 400 nodes, a sweep spec under 10^4.
inline constexpr std::size_t kMaxYamlNodes = 100'000;  ///< nodes, aliases expanded
inline constexpr std::size_t kMaxYamlDepth = 64;       ///< maps and lists within each other

/// Parses `text` (read from `where`) and checks that its top level is a map, before any other
/// reading, that it keeps the limits above. Errors: "where:line: not valid YAML: ...",
/// "where:line: more than 100000 YAML nodes with its aliases expanded (...)", "where:line:
/// nested deeper than 64 maps and lists", "where: expected a map of <what>" and "where:line:
/// key: written twice (also on line N)".
YAML::Node load_yaml_map(const std::string& text, const std::string& where,
                         const std::string& what);

/// The 1-based line `node` was written on, 0 when it was made in code.
int yaml_line(const YAML::Node& node);

/// `value` as YAML (numbers as their JSON text, null as a null node), so that a map of values
/// built in code (a sweep's workload point) is read as a file's map is.
YAML::Node yaml_of_json(const nlohmann::json& value);

class YamlFields {
 public:
  /// `node` must be a map (or null/absent: no fields); `where` is the file name, `prefix` the
  /// dotted path of the map ("frontend"; "" for a file's top level, whose keys are named bare).
  YamlFields(const YAML::Node& node, std::string where, std::string prefix);

  /// The value of `key` (a null node when absent), marking the key as read.
  YAML::Node take(const std::string& key);
  /// What a value is, for "got ..." in errors: its text, or what kind of node it is.
  static std::string described(const YAML::Node& value);

  /// Throws for the first key of the map that was never read: "prefix.key: unknown key", with
  /// " (<accepted>)" after it when `accepted` says which keys are ("expected one of: a, b").
  void finish(const std::string& accepted = {}) const;
  /// finish(), with `sections` (maps parsed by their own readers) counted as read.
  void finish_except(std::initializer_list<const char*> sections);
  /// finish() before reading: every key of the map must be one of `keys` (so that a misspelt key
  /// is the first error, not the missing key it was meant to be).
  void refuse_unknown(const std::vector<std::string>& keys, const std::string& accepted = {});

  /// Fails at the first key of `moved` the map holds: "file:line: prefix.key: moved: now <where
  /// it went> (docs/CONFIG.md)" (keys an older edx read here).
  void refuse_moved(const std::map<std::string, std::string>& moved) const;
  /// "file:line: prefix.key: message" for errors found later (e.g. in validate()). `key` may be
  /// dotted ("units.gemm"): the line is that of the nested key (of the map when it is absent).
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  /// `error`, whose key is relative to this map, placed as fail() places a message.
  [[noreturn]] void fail(const InputError& error) const;
  /// The place of `key` (dotted below this map) in the file.
  InputPlace place_of(const std::string& key) const;
  /// `key` (relative to this map) as a dotted key of the file: "frontend.clock_mhz".
  std::string full_key(const std::string& key) const;
  /// The dotted path of the map ("frontend").
  const std::string& prefix() const { return prefix_; }
  const std::string& where() const { return where_; }

 private:
  YAML::Node node_;
  std::string where_, prefix_;
  std::set<std::string> read_;
};

}  // namespace edx
