#include "common/yaml_fields.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <stdexcept>

namespace edx {
namespace {

std::string line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? std::string() : fmt::format(":{}", mark.line + 1);
}

}  // namespace

/// A key written twice in one map is an error (yaml-cpp keeps both, and lookups would see only
/// the first): "file:line: key: written twice (also on line N)".
static void refuse_duplicate_keys(const YAML::Node& node, const std::string& where,
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
      throw std::runtime_error(
          fmt::format("{}:{}: {}: written twice (also on line {})", where, line, path, it->second));
    }
    refuse_duplicate_keys(item.second, where, path);
  }
}

YAML::Node load_yaml_map(const std::string& text, const std::string& where,
                         const std::string& what) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}:{}: not valid YAML: {}", where, e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) throw std::runtime_error(fmt::format("{}: expected a map of {}", where, what));
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
    throw std::runtime_error(
        fmt::format("{}{}: {}: expected a map of keys", where_, line_of(node_), prefix_));
  }
}

void YamlFields::fail(const std::string& key, const std::string& message) const {
  // The innermost map on the dotted key's path that holds the next part gives the line.
  YAML::Node at = node_;
  std::string line = line_of(node_);
  for (std::size_t start = 0; at && at.IsMap();) {
    const std::size_t dot = key.find('.', start);
    const YAML::Node next = static_cast<const YAML::Node&>(at)[key.substr(start, dot - start)];
    if (!next) break;
    line = line_of(next);
    if (dot == std::string::npos) break;
    at = next;
    start = dot + 1;
  }
  throw std::runtime_error(fmt::format("{}{}: {}.{}: {}", where_, line, prefix_, key, message));
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

void YamlFields::finish() const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& item : node_) {
    const std::string key = item.first.as<std::string>();
    if (!read_.contains(key)) {
      throw std::runtime_error(
          fmt::format("{}{}: {}.{}: unknown key", where_, line_of(item.first), prefix_, key));
    }
  }
}

}  // namespace edx
