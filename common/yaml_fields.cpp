#include "common/yaml_fields.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>

namespace edx {
namespace {

/// A key written twice in one map is an error (yaml-cpp keeps both, and lookups would see only
/// the first): "file:line: key: written twice (also on line N)".
void refuse_duplicate_keys(const YAML::Node& node, const std::string& where,
                           const std::string& prefix) {
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      refuse_duplicate_keys(node[i], where, fmt::format("{}[{}]", prefix, i));
    }
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> lines;
  for (const auto& item : node) {
    const std::string key = item.first.IsScalar() ? item.first.Scalar() : std::string();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    const int line = item.first.Mark().line + 1;
    if (const auto [it, inserted] = lines.emplace(key, line); !inserted) {
      throw InputError({where, line}, path,
                       fmt::format("written twice (also on line {})", it->second));
    }
    refuse_duplicate_keys(item.second, where, path);
  }
}

/// Walks `node` as its readers will, aliases expanded, counting the nodes it stands for into
/// `nodes`; stops at the first node past kMaxYamlNodes or kMaxYamlDepth, so the walk itself
/// costs at most kMaxYamlNodes visits whatever the document.
void check_yaml_limits(const YAML::Node& node, std::size_t depth, std::size_t& nodes,
                       const std::string& where) {
  if (++nodes > kMaxYamlNodes) {
    throw InputError({where, yaml_line(node)}, "",
                     fmt::format("more than {} YAML nodes with its aliases expanded (nested "
                                 "anchors? edx reads documents of at most {} nodes)",
                                 kMaxYamlNodes, kMaxYamlNodes));
  }
  if (!node.IsMap() && !node.IsSequence()) return;
  if (depth >= kMaxYamlDepth) {
    throw InputError({where, yaml_line(node)}, "",
                     fmt::format("nested deeper than {} maps and lists", kMaxYamlDepth));
  }
  for (const auto& item : node) {
    if (node.IsMap()) {
      check_yaml_limits(item.first, depth + 1, nodes, where);
      check_yaml_limits(item.second, depth + 1, nodes, where);
    } else {
      check_yaml_limits(item, depth + 1, nodes, where);
    }
  }
}

}  // namespace

int yaml_line(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

std::string read_input_file(const std::filesystem::path& path, const std::string& what) {
  // A folder opens as a stream that reads nothing (Linux), which would be parsed as an empty
  // document ("expected a map"): named as what it is.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError({path.string()}, "", "is a directory (expected a " + what + ")");
  }
  std::ifstream in(path);
  if (!in) throw InputError({path.string()}, "", "cannot read the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

YAML::Node yaml_of_json(const nlohmann::json& value) {
  if (value.is_object()) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& [key, item] : value.items()) map[key] = yaml_of_json(item);
    return map;
  }
  if (value.is_array()) {
    YAML::Node list(YAML::NodeType::Sequence);
    for (const nlohmann::json& item : value) list.push_back(yaml_of_json(item));
    return list;
  }
  if (value.is_null()) return YAML::Node(YAML::NodeType::Null);
  if (value.is_string()) return YAML::Node(value.get<std::string>());
  // A whole number written as 15.0 is 15 (an integer key reads it).
  if (const double v = value.is_number_float() ? value.get<double>() : 0.5;
      std::abs(v) < 9e15 && v == std::round(v)) {
    return YAML::Node(fmt::format("{}", static_cast<std::int64_t>(v)));
  }
  return YAML::Node(value.dump());
}

YAML::Node load_yaml_map(const std::string& text, const std::string& where,
                         const std::string& what) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError({where, e.mark.line + 1}, "", "not valid YAML: " + e.msg);
  }
  std::size_t nodes = 0;
  check_yaml_limits(root, 0, nodes, where);
  if (!root.IsMap()) throw InputError({where}, "", "expected a map of " + what);
  refuse_duplicate_keys(root, where, "");
  return root;
}

std::string YamlFields::described(const YAML::Node& v) {
  if (v.IsScalar()) return v.Scalar();
  if (v.IsNull()) return "nothing (~ or an empty value)";
  return v.IsMap() ? "a map" : "a list";
}

YamlFields::YamlFields(const YAML::Node& node, std::string where, std::string prefix)
    : node_(node), where_(std::move(where)), prefix_(std::move(prefix)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw InputError({where_, yaml_line(node_)}, prefix_, "expected a map of keys");
  }
}

std::string YamlFields::full_key(const std::string& key) const {
  if (prefix_.empty()) return key;
  return key.empty() ? prefix_ : prefix_ + "." + key;
}

InputPlace YamlFields::place_of(const std::string& key) const {
  // The innermost map on the dotted key's path that holds the next part gives the line. The
  // walk keeps its own handles: assigning to a YAML::Node would rebind the node it refers to,
  // changing the document.
  int line = node_ ? yaml_line(node_) : 0;
  std::vector<YAML::Node> path{node_};
  for (std::size_t start = 0; path.back() && path.back().IsMap();) {
    const std::size_t dot = key.find('.', start);
    const YAML::Node next =
        static_cast<const YAML::Node&>(path.back())[key.substr(start, dot - start)];
    if (!next) break;
    line = yaml_line(next);
    if (dot == std::string::npos) break;
    path.push_back(next);
    start = dot + 1;
  }
  return {where_, line};
}

void YamlFields::fail(const std::string& key, const std::string& message) const {
  fail(InputError({}, key, message));
}

void YamlFields::fail(const InputError& error) const {
  throw error.with_key(full_key(error.key())).at(place_of(error.key()));
}

void YamlFields::refuse_moved(const std::map<std::string, std::string>& moved) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& [key, now] : moved) {
    if (static_cast<const YAML::Node&>(node_)[key]) {
      fail(key, fmt::format("moved: now {} (docs/CONFIG.md)", now));
    }
  }
}

YAML::Node YamlFields::take(const std::string& key) {
  read_.insert(key);
  // Undefined (false), not YAML::Node() (a defined null), when there is no such key.
  if (!node_ || !node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  return static_cast<const YAML::Node&>(node_)[key];
}

void YamlFields::finish_except(std::initializer_list<const char*> sections) {
  for (const char* section : sections) read_.insert(section);
  finish();
}

void YamlFields::refuse_unknown(const std::vector<std::string>& keys, const std::string& accepted) {
  read_.insert(keys.begin(), keys.end());
  finish(accepted);
}

void YamlFields::finish(const std::string& accepted) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& item : node_) {
    const std::string key = item.first.as<std::string>();
    if (!read_.contains(key)) {
      throw InputError(
          {where_, yaml_line(item.first)}, full_key(key),
          accepted.empty() ? "unknown key" : fmt::format("unknown key ({})", accepted));
    }
  }
}

}  // namespace edx
