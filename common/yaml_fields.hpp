#pragma once
// One YAML map of a platform config, read key by key (config_fields.hpp's parse_fields), with
// errors that name the file, line and key: "car.yaml:12: frontend.clock_mhz: expected a number
// in (0, 1000], got 'fast'". Unknown keys are errors too (finish(): the keys never taken).
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <map>
#include <set>
#include <string>

namespace edx {

/// Parses `text` (read from `where`) and checks that its top level is a map. Errors:
/// "where:line: not valid YAML: ..." and "where: expected a map of <what>".
YAML::Node load_yaml_map(const std::string& text, const std::string& where,
                         const std::string& what);

class YamlFields {
 public:
  /// `node` must be a map (or null/absent: no fields); `where` is the file name, `prefix` the
  /// dotted path of the map ("frontend").
  YamlFields(const YAML::Node& node, std::string where, std::string prefix);

  /// The value of `key` (a null node when absent), marking the key as read.
  YAML::Node take(const std::string& key);
  /// What a value is, for "got ..." in errors: its text, or what kind of node it is.
  static std::string described(const YAML::Node& value);

  /// Throws for every key of the map that was never read (the first one, with its line).
  void finish() const;
  /// finish(), with `sections` (maps parsed by their own readers) counted as read.
  void finish_except(std::initializer_list<const char*> sections);

  /// Fails at the first key of `moved` the map holds: "file:line: prefix.key: moved: now <where
  /// it went> (docs/CONFIG.md)" (keys an older edx read here).
  void refuse_moved(const std::map<std::string, std::string>& moved) const;
  /// "file:line: prefix.key: message" for errors found later (e.g. in validate()). `key` may be
  /// dotted ("units.gemm"): the line is that of the nested key.
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  /// The dotted path of the map ("frontend").
  const std::string& prefix() const { return prefix_; }
  const std::string& where() const { return where_; }

 private:
  YAML::Node node_;
  std::string where_, prefix_;
  std::set<std::string> read_;
};

}  // namespace edx
