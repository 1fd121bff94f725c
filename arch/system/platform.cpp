#include "arch/system/platform.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "arch/common/yaml_fields.hpp"
#include "arch/memory/bram.hpp"

namespace edx::arch {

nlohmann::json HostConfig::to_json() const {
  return {{"name", name}, {"frontend_time_scale", frontend_time_scale}, {"provenance", provenance}};
}

nlohmann::json Platform::to_json() const {
  return {{"name", name},
          {"description", description},
          {"device", device},
          {"host", host.to_json()},
          {"frontend", frontend.to_json()},
          {"link", link.to_json()},
          {"transfers", transfers.to_json()}};
}

Platform Platform::parse(const std::string& text, const std::string& where) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}:{}: not valid YAML: {}", where, e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) throw std::runtime_error(fmt::format("{}: expected a map of sections", where));
  Platform p;
  YamlFields top(root, where, "platform");
  top.read("name", p.name);
  top.read("description", p.description);
  top.read("device", p.device);
  // Sections are parsed by their own structs; mark them read here.
  std::string ignored;
  for (const char* section : {"host", "frontend", "link", "transfers"}) {
    if (root[section] && !root[section].IsMap()) top.fail(section, "expected a map of keys");
  }
  top.finish_except({"host", "frontend", "link", "transfers"});
  if (p.name.empty()) top.fail("name", "required: the platform's name");
  try {
    Device::by_name(p.device);
  } catch (const std::runtime_error& e) {
    top.fail("device", e.what());
  }
  YamlFields host(root["host"], where, "host");
  host.read("name", p.host.name);
  host.read("frontend_time_scale", p.host.frontend_time_scale, 0.0);
  host.read("provenance", p.host.provenance);
  host.finish();
  p.frontend = FrontendConfig::from_yaml(root["frontend"], where);
  if (root["link"]) p.link = LinkSpec::from_yaml(root["link"], where);
  p.transfers = FrameTransferConfig::from_yaml(root["transfers"], where);
  return p;
}

Platform Platform::load(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(fmt::format("{}: cannot read the platform file", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path.string());
}

}  // namespace edx::arch
