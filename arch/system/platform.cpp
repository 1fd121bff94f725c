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
  return {{"name", name},
          {"frontend_time_scale", frontend_time_scale},
          {"provenance", provenance},
          {"backend_time_scale", backend_time_scale},
          {"backend_provenance", backend_provenance}};
}

nlohmann::json SchedulerConfig::to_json() const {
  return {{"policy", to_string(policy)}, {"training_fraction", training_fraction}};
}

nlohmann::json Platform::to_json() const {
  return {{"name", name},
          {"description", description},
          {"device", device},
          {"host", host.to_json()},
          {"frontend", frontend.to_json()},
          {"link", link.to_json()},
          {"transfers", transfers.to_json()},
          {"backend", backend.to_json()},
          {"cost", cost.to_json()},
          {"power", power.to_json()},
          {"scheduler", scheduler.to_json()}};
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
  for (const char* section :
       {"host", "frontend", "backend", "link", "transfers", "cost", "power", "scheduler"}) {
    if (root[section] && !root[section].IsMap()) top.fail(section, "expected a map of keys");
  }
  top.finish_except(
      {"host", "frontend", "backend", "link", "transfers", "cost", "power", "scheduler"});
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
  host.read("backend_time_scale", p.host.backend_time_scale, 0.0);
  host.read("backend_provenance", p.host.backend_provenance);
  host.finish();
  p.frontend = FrontendConfig::from_yaml(root["frontend"], where);
  if (root["link"]) p.link = LinkSpec::from_yaml(root["link"], where);
  p.transfers = FrameTransferConfig::from_yaml(root["transfers"], where);
  p.backend = BackendConfig::from_yaml(root["backend"], where);
  p.cost = cost::CostConfig::from_yaml(root["cost"], where);
  p.power = cost::PowerConfig::from_yaml(root["power"], where);
  YamlFields sched(root["scheduler"], where, "scheduler");
  std::string policy = to_string(p.scheduler.policy);
  sched.read("policy", policy);
  sched.read("training_fraction", p.scheduler.training_fraction, -1e-12);
  sched.finish();
  try {
    p.scheduler.policy = parse_offload_policy(policy);
  } catch (const std::runtime_error&) {
    sched.fail("policy",
               fmt::format("expected never, always, regression or oracle, got '{}'", policy));
  }
  if (!(p.scheduler.training_fraction < 1.0)) {
    sched.fail("training_fraction", "expected a fraction in [0, 1)");
  }
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
