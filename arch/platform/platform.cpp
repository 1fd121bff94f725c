#include "arch/platform/platform.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <stdexcept>

#include "arch/memory/bram.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {

const FieldList<SchedulerConfig>& SchedulerConfig::fields() {
  using C = SchedulerConfig;
  static const FieldList<C> list = {
      enum_field(
          "policy", &C::policy, {"never", "always", "regression", "oracle"},
          [](OffloadPolicy p) { return std::string(to_string(p)); },
          [](const std::string& text) { return parse_offload_policy(text); },
          "which accelerable kernel invocations run on the FPGA (Sec. VI-B)"),
      field("training_fraction", &C::training_fraction, "",
            "leading share of each kernel's invocations its regression is fitted on (they run on "
            "the host)",
            Bounds::at_least(0).below(1)),
      choice_field(
          "offload", &C::offload, "",
          [] {
            std::vector<std::string> names;
            for (const AccelerableKernel* k : accelerable_kernels()) {
              names.emplace_back(k->name);
            }
            return names;
          }(),
          "the kernels that may run on the backend units (their ops: recorded in the "
          "trace or derived from their sizes)"),
  };
  return list;
}

bool SchedulerConfig::offloads(const std::string& kernel) const {
  return std::find(offload.begin(), offload.end(), kernel) != offload.end();
}

void SchedulerConfig::validate() const { check_fields(*this, "scheduler", fields()); }

nlohmann::json SchedulerConfig::to_json() const { return fields_to_json(*this, fields()); }

void Platform::validate() const {
  check_fields(*this, "platform", fields());
  if (host == nullptr) throw std::runtime_error("host: no host processor");
  frontend.validate();
  if (!link || !memory) {
    throw std::runtime_error("platform: expected a link and a memory component");
  }
  transfers.validate();
  if (backend == nullptr) throw std::runtime_error("backend: no offload accelerator");
  cost.validate();
  power.validate();
  scheduler.validate();
  system.validate();
  ros.validate();
}

const FieldList<Platform>& Platform::fields() {
  using C = Platform;
  static const FieldList<C> list = {
      field("name", &C::name, "", "the platform's name (required)"),
      field("description", &C::description, "", "one line for reports"),
      field("device", &C::device, "",
            "the FPGA: xc7v690t (Virtex-7, Edx-Car), zu9eg or zu9cg (Zynq UltraScale+, "
            "Edx-Drone)"),
  };
  return list;
}

std::vector<ReferenceRow> Platform::reference() {
  std::vector<ReferenceRow> rows = {reference_row(
      "", "extends", FieldKind::kText, "", std::string(), {}, {},
      "a platform file this one starts from (its keys override the parent's, map by map)")};
  const auto add = [&rows](std::vector<ReferenceRow> more) {
    for (ReferenceRow& row : more) rows.push_back(std::move(row));
  };
  add(reference_rows("", fields()));
  add(component_reference<HostProcessor>("host", kDefaultHostKind));
  add({reference_row("", "baseline_host", FieldKind::kText, "", std::string(), {}, {},
                     "the CPU-only baseline's host when it is another CPU than `host` (a map "
                     "with the keys of `host`, any kind; absent: the baseline runs on `host`)")});
  add(component_reference<Coprocessor>("coprocessor", ""));
  add(FrontendConfig::reference());
  add(component_reference<OffloadAccelerator>("backend", kDefaultOffloadKind));
  add(component_reference<Link>("link", kDefaultLinkKind));
  add(component_reference<OnChipMemory>("memory", kDefaultMemoryKind));
  add(reference_rows("transfers", FrameTransferConfig::fields()));
  add(reference_rows("cost", cost::CostConfig::fields()));
  add(reference_rows("power", cost::PowerConfig::fields()));
  add(reference_rows("scheduler", SchedulerConfig::fields()));
  add(reference_rows("system", SystemConfig::fields()));
  add(reference_rows("ros", RosTransport::fields()));
  return rows;
}

nlohmann::json Platform::to_json() const {
  nlohmann::json j = {{"name", name},
                      {"description", description},
                      {"device", device},
                      {"host", component_json(*host)},
                      {"frontend", frontend.to_json()},
                      {"link", component_json(*link)},
                      {"memory", component_json(*memory)},
                      {"transfers", transfers.to_json()},
                      {"backend", component_json(*backend)},
                      {"cost", cost.to_json()},
                      {"power", power.to_json()},
                      {"scheduler", scheduler.to_json()},
                      {"system", system.to_json()}};
  if (baseline_host) j["baseline_host"] = component_json(*baseline_host);
  if (coprocessor) j["coprocessor"] = component_json(*coprocessor);
  if (ros.enabled) j["ros"] = ros.to_json();  // absent while off: the hashes of runs without it
  return j;
}

std::string config_reference_markdown() {
  return "# Platform configuration reference\n\n"
         "Every key a platform file (`configs/*.yaml`) may hold, section by section: its type, "
         "unit, default (the value when the key is absent) and the values it accepts. Generated "
         "by `edx config --reference` from the field list each config struct declares "
         "(`common/config_fields.hpp`); a test fails when this file is not its current "
         "output. What each value means for the model, and where it comes from, is in "
         "[MODEL.md](MODEL.md); the Edx-Car and Edx-Drone values are in `configs/`.\n\n"
         "Unknown keys, a key written twice and a value outside what its key accepts are errors "
         "naming the file, line and key.\n\n"
         "The frontend's and the backend's units are instances of registered unit kinds "
         "(`frontend.units.<task>`, one per task of the graph; `backend.units.<name>`): each "
         "instance names its `kind`, has the instance keys (`count`, `clock_mhz`, ...) and its "
         "kind's own keys, listed per kind below. A section's `units` map is read over the "
         "paper's units: a listed instance overrides the default of its name (its kind kept "
         "unless given), a new name adds a unit. The host (`host:`) is one instance of a "
         "registered host processor kind, named by `host.kind` (optional; default "
         "`suite_scaled`), its keys listed per kind below; the `backend:` section is the offload "
         "accelerator, itself a kind (`backend.kind`, by default the paper's `fpga_matrix_units`). "
         "The link (`link:`) and the on-chip memory (`memory:`) are one component each: `kind` "
         "names it (default `dma` and `bram`) and the other keys are that kind's. The `dma` "
         "link's `preset` sets its keys before the others are read; its defaults below are "
         "`pcie3_x8`'s. A kind is one source file registering itself (arch/frontend/units/, "
         "arch/backend/units/, arch/backend/accelerators/, arch/host/processors/, "
         "arch/link/kinds/, arch/memory/kinds/; docs/MODEL.md, \"Components\").\n" +
         render_reference(Platform::reference());
}

namespace {

YAML::Node load_yaml(const std::string& text, const std::string& where) {
  return load_yaml_map(text, where, "sections");
}

/// Records `file` as the origin of every key under `node` (dotted from `prefix`).
void note_origins(const YAML::Node& node, const std::string& prefix, const std::string& file,
                  std::map<std::string, InputPlace>& origins) {
  if (!node.IsMap()) return;
  for (const auto& item : node) {
    const std::string key =
        prefix.empty() ? item.first.Scalar() : prefix + "." + item.first.Scalar();
    origins[key] = {file};
    note_origins(item.second, key, file, origins);
  }
}

/// child over parent, recursively by map; `parent` is modified in place (a clone).
void merge_into(YAML::Node parent, const YAML::Node& child) {
  for (const auto& item : child) {
    const std::string key = item.first.Scalar();
    // A const lookup: the non-const one would leave an empty entry behind for a new key.
    YAML::Node existing = static_cast<const YAML::Node&>(parent)[key];
    if (existing && existing.IsMap() && item.second.IsMap()) {
      merge_into(existing, item.second);
    } else {
      // Insert the child's own key node: errors then still point at the child's line.
      if (existing) parent.remove(key);
      parent.force_insert(item.first, item.second);
    }
  }
}

PlatformSource load_chain(const std::filesystem::path& path, std::vector<std::string>& chain) {
  YAML::Node root = load_yaml(read_input_file(path, "platform file"), path.string());
  PlatformSource source;
  source.file = path.string();
  const YAML::Node extends = root["extends"];
  if (extends) {
    const InputPlace at{path.string(), yaml_line(extends)};
    if (!extends.IsScalar() || extends.Scalar().empty()) {
      throw InputError(at, "platform.extends", "expected a file name");
    }
    const std::filesystem::path parent = path.parent_path() / extends.Scalar();
    const std::string canonical = std::filesystem::weakly_canonical(parent).string();
    if (std::find(chain.begin(), chain.end(), canonical) != chain.end()) {
      throw InputError(at, "platform.extends",
                       fmt::format("'{}' extends itself (cycle: {})", extends.Scalar(),
                                   fmt::join(chain, " -> ")));
    }
    if (!std::filesystem::is_regular_file(parent)) {
      throw InputError(at, "platform.extends", fmt::format("no such file '{}'", parent.string()));
    }
    chain.push_back(canonical);
    source = load_chain(parent, chain);
    source.file = path.string();
    root.remove("extends");
    merge_into(source.root, root);
  } else {
    source.root = root;
  }
  note_origins(root, "", path.string(), source.origins);
  return source;
}

/// Parses the merged `root`; `where` names it in errors.
Platform parse_root(const YAML::Node& root, const std::string& where) {
  Platform p;
  YamlFields top(root, where, "platform");
  parse_fields(top, p, Platform::fields());
  // Sections are parsed by their own structs; mark them read here.
  for (const char* section :
       {"host", "baseline_host", "coprocessor", "frontend", "backend", "link", "memory",
        "transfers", "cost", "power", "scheduler", "system", "ros"}) {
    if (root[section] && !root[section].IsMap()) top.fail(section, "expected a map of keys");
  }
  top.finish_except({"host", "baseline_host", "coprocessor", "frontend", "backend", "link",
                     "memory", "transfers", "cost", "power", "scheduler", "system", "ros"});
  if (p.name.empty()) top.fail("name", "required: the platform's name");
  if (!Device::find(p.device)) {
    top.fail(InputError::expected("device", Device::known_names(), p.device));
  }
  YamlFields host(root["host"], where, "host");
  p.host = parse_component<HostProcessor>(host, kDefaultHostKind);
  if (root["baseline_host"]) {
    YamlFields baseline_host(root["baseline_host"], where, "baseline_host");
    p.baseline_host = parse_component<HostProcessor>(baseline_host, kDefaultHostKind);
  }
  if (root["coprocessor"]) {
    YamlFields coprocessor(root["coprocessor"], where, "coprocessor");
    p.coprocessor = parse_component<Coprocessor>(coprocessor, "");
  }
  p.frontend = FrontendConfig::from_yaml(root["frontend"], where);
  YamlFields link(root["link"], where, "link");
  p.link = parse_component<Link>(link, kDefaultLinkKind);
  YamlFields memory(root["memory"], where, "memory");
  p.memory = parse_component<OnChipMemory>(memory, kDefaultMemoryKind);
  p.transfers = FrameTransferConfig::from_yaml(root["transfers"], where);
  YamlFields backend(root["backend"], where, "backend");
  p.backend = parse_component<OffloadAccelerator>(backend, kDefaultOffloadKind);
  p.cost = cost::CostConfig::from_yaml(root["cost"], where);
  p.power = cost::PowerConfig::from_yaml(root["power"], where);
  p.system = SystemConfig::from_yaml(root["system"], where);
  p.ros = RosTransport::from_yaml(root["ros"], where);
  p.scheduler = parse_section<SchedulerConfig>(root["scheduler"], where, "scheduler");
  return p;
}

}  // namespace

PlatformSource PlatformSource::load(const std::filesystem::path& path) {
  std::vector<std::string> chain{std::filesystem::weakly_canonical(path).string()};
  return load_chain(path, chain);
}

void PlatformSource::set(const std::string& key, const YAML::Node& value, InputPlace origin) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  // Walk with owned nodes (operator= on a YAML::Node handle would rebind, not descend).
  std::vector<YAML::Node> path{root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = path.back()[parts[i]];
    if (next && !next.IsMap() && !next.IsNull()) {
      // A key under a value (backend.spm_bytes.x): the setter's error, not the platform file's.
      std::string prefix = parts[0];
      for (std::size_t j = 1; j <= i; ++j) prefix += "." + parts[j];
      throw InputError(origin, key,
                       fmt::format("'{}' is a value of the platform, not a map of keys", prefix));
    }
    if (!next || !next.IsMap()) {
      path.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = path.back()[parts[i]];
    }
    path.push_back(next);
  }
  path.back()[parts.back()] = value;
  origins[key] = std::move(origin);
}

Platform Platform::parse(const std::string& text, const std::string& where) {
  const YAML::Node root = load_yaml(text, where);
  if (root["extends"]) {
    throw InputError({where, yaml_line(root["extends"])}, "platform.extends",
                     "only a platform file can extend another (load it with its path)");
  }
  return parse_root(root, where);
}

Platform Platform::parse(const PlatformSource& source) {
  try {
    return parse_root(source.root, source.file);
  } catch (const InputError& e) {
    // The merged tree's nodes keep their lines; the file is the one that wrote the longest known
    // prefix of the key (a top-level key is reported as "platform.key").
    std::string key = e.key().starts_with("platform.") ? e.key().substr(9) : e.key();
    for (; !key.empty(); key = key.substr(0, key.rfind('.'))) {
      if (const auto it = source.origins.find(key); it != source.origins.end()) {
        InputPlace origin = it->second;
        if (origin.line == 0) origin.line = e.line();
        throw e.at(origin);
      }
      if (key.find('.') == std::string::npos) break;
    }
    throw;
  }
}

Platform Platform::load(const std::filesystem::path& path) {
  return parse(PlatformSource::load(path));
}

}  // namespace edx::arch
