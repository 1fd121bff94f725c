#pragma once
// Reading one YAML map of a platform config into a plain struct, field by field, with errors
// that name the file, line and key: "car.yaml:12: frontend.clock_mhz: expected a number > 0,
// got 'fast'". Unknown keys are errors too (finish() lists the keys that were read).
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <set>
#include <string>

namespace edx::arch {

/// Parses `text` (read from `where`) and checks that its top level is a map. Errors:
/// "where:line: not valid YAML: ..." and "where: expected a map of <what>".
YAML::Node load_yaml_map(const std::string& text, const std::string& where,
                         const std::string& what);

class YamlFields {
 public:
  /// `node` must be a map (or null/absent: no fields); `where` is the file name, `prefix` the
  /// dotted path of the map ("frontend").
  YamlFields(const YAML::Node& node, std::string where, std::string prefix);

  /// Reads `key` into `value` when present. Numbers must be finite; `min_exclusive` bounds.
  void read(const std::string& key, double& value, double min_exclusive);
  void read(const std::string& key, int& value, int min_inclusive);
  void read(const std::string& key, bool& value);
  void read(const std::string& key, std::string& value);

  /// Throws for every key of the map that was never read (the first one, with its line).
  void finish() const;
  /// finish(), with `sections` (maps parsed by their own readers) counted as read.
  void finish_except(std::initializer_list<const char*> sections);

  /// "file:line: prefix.key: message" for errors found later (e.g. in validate()).
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  YAML::Node node_;
  std::string where_, prefix_;
  std::set<std::string> read_;
};

}  // namespace edx::arch
