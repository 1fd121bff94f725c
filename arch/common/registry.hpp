#pragma once
// Component registries in the manner of Ramulator 2 (../shared/STYLE.md; docs/MODEL.md
// "Components"): one interface per component kind (a backend matrix unit, a frontend unit, a
// memory, a link, a host processor, an offload accelerator), its implementations beside it, each
// registered by name with one line in its own file:
//
//   class SystolicArray final : public MatrixUnit { public: struct Params {...}; ... };
//   EDX_REGISTER_COMPONENT(MatrixUnit, SystolicArray, "systolic_array", "b x b array of MACs");
//
// An implementation owns its parameters: a `Params` struct that declares its keys once (a field
// list, config_fields.hpp: key, unit, range, doc), and a constructor from it. From that one
// declaration the registry parses an instance's YAML map (each value checked at its file:line,
// unknown keys refused), prints its parameters as JSON (results, config hashes) and lists them
// in `edx config --reference` (docs/CONFIG.md). A platform names the implementation with
// `kind:`; adding a kind touches no other file.
//
// The implementation's Params must provide
//   static const FieldList<Params>& fields();   every key, once
//   void validate() const;                      rules between fields (check_fields at least)
// and may provide `static Params parse(YamlFields&)` when it reads more than its field list
// (nested sections, presets); the registry still refuses the keys it leaves unread. Such a kind
// lists those keys too with `static std::vector<ReferenceRow> reference(const std::string&
// section, const std::string& title)` (its rows under `section`, in the table headed `title`).
// and the implementation `explicit Impl(const Params&)` and `const Params& params() const`.
#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "common/config_fields.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {

/// What every component implementation answers, whatever its kind.
class Component {
 public:
  virtual ~Component() = default;
  /// The registered name of its implementation ("systolic_array").
  virtual std::string_view kind() const = 0;
  /// Its parameters as JSON (every key, defaults included): results and config hashes.
  virtual nlohmann::json params_json() const = 0;
};

/// One registered implementation of an interface.
template <class Interface>
struct ComponentEntry {
  std::string name;  ///< the `kind:` that selects it
  std::string doc;   ///< one line: what it is, and its source
  /// Reads an instance's parameters from `fields` (its YAML map, the instance keys already
  /// taken by the caller) over the defaults and builds it; errors name file, line and key.
  std::function<std::shared_ptr<const Interface>(YamlFields& fields)> parse;
  /// An instance with every parameter at its default.
  std::function<std::shared_ptr<const Interface>()> make_default;
  /// Its parameters' reference rows under `section` ("backend.units.<name>"), in a table headed
  /// "`section` of kind `name`: doc".
  std::function<std::vector<ReferenceRow>(const std::string& section)> reference;
};

/// The implementations of one interface, by name.
template <class Interface>
class ComponentRegistry {
 public:
  static ComponentRegistry& instance() {
    static ComponentRegistry registry;
    return registry;
  }

  /// Registers `entry`; a second implementation of the same name is a programming error,
  /// reported at start-up (std::logic_error).
  bool add(ComponentEntry<Interface> entry) {
    const std::string name = entry.name;
    if (!entries_.emplace(name, std::move(entry)).second) {
      throw std::logic_error(
          fmt::format("{}: two implementations registered as '{}'", Interface::kKindName, name));
    }
    return true;
  }

  /// The implementation called `name`, nullptr when there is none.
  const ComponentEntry<Interface>* find(std::string_view name) const {
    const auto it = entries_.find(std::string(name));
    return it == entries_.end() ? nullptr : &it->second;
  }

  /// The implementation called `name`; throws std::runtime_error "expected <kinds>" otherwise.
  const ComponentEntry<Interface>& at(std::string_view name) const {
    if (const auto* entry = find(name)) return *entry;
    throw std::runtime_error(
        fmt::format("expected a {} kind ({}), got '{}'", Interface::kKindName, names(), name));
  }

  /// Every implementation, by name.
  std::vector<const ComponentEntry<Interface>*> entries() const {
    std::vector<const ComponentEntry<Interface>*> out;
    for (const auto& [name, entry] : entries_) out.push_back(&entry);
    return out;
  }

  /// "a, b or c".
  std::string names() const {
    std::string text;
    std::size_t i = 0;
    for (const auto& [name, entry] : entries_) {
      text += i == 0 ? "" : (i + 1 == entries_.size() ? " or " : ", ");
      text += name;
      ++i;
    }
    return text;
  }

  /// The default instance of `name` (code that builds a platform without YAML).
  std::shared_ptr<const Interface> make(std::string_view name) const {
    return at(name).make_default();
  }

 private:
  std::map<std::string, ComponentEntry<Interface>> entries_;
};

/// The registry entry of implementation `Impl` of `Interface` (see the header comment).
template <class Interface, class Impl>
ComponentEntry<Interface> component_entry(std::string name, std::string doc) {
  using Params = typename Impl::Params;
  ComponentEntry<Interface> e;
  e.name = std::move(name);
  e.doc = std::move(doc);
  e.parse = [](YamlFields& fields) -> std::shared_ptr<const Interface> {
    Params params;
    if constexpr (requires { Params::parse(fields); }) {
      params = Params::parse(fields);  // a kind with nested sections or presets reads its own
    } else {
      parse_fields(fields, params, Params::fields());
    }
    fields.finish();
    validate_at(fields, [&params] { params.validate(); });
    return std::make_shared<const Impl>(params);
  };
  e.make_default = []() -> std::shared_ptr<const Interface> {
    return std::make_shared<const Impl>(Params{});
  };
  e.reference = [name = e.name, doc = e.doc](const std::string& section) {
    const std::string title = fmt::format("`{}` of kind `{}`: {}", section, name, doc);
    if constexpr (requires { Params::reference(section, title); }) {
      return Params::reference(section, title);  // presets, nested sections
    } else {
      return reference_rows(section, Params::fields(), Params{}, title);
    }
  };
  return e;
}

/// Instances of a component kind, as a platform section lists them: a map of named instances,
/// each `{kind: K, <instance keys>, <K's own keys>}`, over a list of defaults. A listed name among
/// the defaults overrides that instance (its kind kept unless given, every key over its default);
/// a new name adds an instance, its kind required. `Instance` has `name`, `unit` (a
/// std::shared_ptr<const Interface>) and a field list of its instance keys (`fields()`).
/// `prepare(instance)` sets the defaults of the instance keys before they are read (e.g. a
/// precision that follows the section's scalar format). Errors name file, line and key.
template <class Interface, class Instance>
void parse_instances(const YAML::Node& map, const std::string& where, const std::string& prefix,
                     std::vector<Instance>& instances,
                     const std::function<void(std::type_identity_t<Instance>&)>& prepare = {}) {
  const auto& registry = ComponentRegistry<Interface>::instance();
  for (const auto& item : map) {
    const std::string name = item.first.Scalar();
    const auto it = std::find_if(instances.begin(), instances.end(),
                                 [&](const Instance& i) { return i.name == name; });
    YamlFields fields(item.second, where, prefix + "." + name);
    const YAML::Node kind = fields.take("kind");
    if ((!kind && it == instances.end()) || (kind && !kind.IsScalar())) {
      fields.fail("kind", fmt::format("required for a unit not among the defaults: one of {}",
                                      registry.names()));
    }
    const std::string kind_name = kind ? kind.Scalar() : std::string(it->unit->kind());
    const ComponentEntry<Interface>* entry = registry.find(kind_name);
    if (entry == nullptr) {
      fields.fail("kind", fmt::format("expected one of {}, got '{}'", registry.names(), kind_name));
    }
    Instance instance;
    instance.name = name;
    if (prepare) prepare(instance);
    parse_fields(fields, instance, Instance::fields());
    instance.unit = entry->parse(fields);  // the kind's keys; unknown keys refused there
    if (it != instances.end()) {
      *it = std::move(instance);
    } else {
      instances.push_back(std::move(instance));
    }
  }
}

/// An instance as JSON: its kind, its instance keys and its kind's parameters.
template <class Instance>
nlohmann::json instance_json(const Instance& instance) {
  nlohmann::json j = {{"kind", std::string(instance.unit->kind())}};
  j.update(fields_to_json(instance, Instance::fields()));
  j.update(instance.unit->params_json());
  return j;
}

/// The reference of a section's instances (`section` "backend.units", an instance written
/// `placeholder`, "<name>"): `kind` (`defaults` describes the default instances' kinds), the
/// instance keys, then every registered kind's own keys, each kind in a table of its own.
template <class Interface, class Instance>
std::vector<ReferenceRow> instance_reference(const std::string& section,
                                             const std::string& placeholder,
                                             const std::string& defaults) {
  const std::string at = section + "." + placeholder;
  const auto& registry = ComponentRegistry<Interface>::instance();
  std::vector<std::string> kinds;
  for (const auto* e : registry.entries()) kinds.push_back(e->name);
  std::vector<ReferenceRow> rows = {reference_row(
      at, "kind", FieldKind::kText, "", std::string(), {}, kinds,
      fmt::format("the unit's kind: required for a unit not among the defaults, which keep "
                  "theirs ({}); its own keys follow",
                  defaults))};
  for (ReferenceRow& row : reference_rows(at, Instance::fields())) rows.push_back(std::move(row));
  for (const auto* entry : registry.entries()) {
    for (ReferenceRow& row : entry->reference(at)) rows.push_back(std::move(row));
  }
  return rows;
}

/// An instance of implementation `kind` of `Interface` with `params` (YAML text of its keys, e.g.
/// "{block: 8}") over its defaults: code and tests that build a component without a platform
/// file. Errors name "code" and the keys under `prefix` ("link").
template <class Interface>
std::shared_ptr<const Interface> make_component(std::string_view kind, const std::string& params,
                                                const std::string& prefix) {
  YamlFields fields(YAML::Load(params), "code", prefix);
  return ComponentRegistry<Interface>::instance().at(kind).parse(fields);
}

/// The JSON of an implementation's parameters (its params_json()).
template <class Params>
nlohmann::json params_to_json(const Params& params) {
  return fields_to_json(params, Params::fields());
}

/// A section that holds one component (`host:`, `link:`, `memory:`, `backend:`):
/// `{kind: K, <K's own keys>}`, `kind` optional (`default_kind` when absent). `fields` is the
/// section's map; every other key is the kind's, unknown keys refused. Errors name file, line
/// and key.
template <class Interface>
std::shared_ptr<const Interface> parse_component(YamlFields& fields,
                                                 std::string_view default_kind) {
  const auto& registry = ComponentRegistry<Interface>::instance();
  const YAML::Node kind = fields.take("kind");
  if (kind && !kind.IsScalar()) {
    fields.fail("kind", fmt::format("expected one of {}", registry.names()));
  }
  const std::string kind_name = kind ? kind.Scalar() : std::string(default_kind);
  const ComponentEntry<Interface>* entry = registry.find(kind_name);
  if (entry == nullptr) {
    fields.fail("kind", fmt::format("expected one of {}, got '{}'", registry.names(), kind_name));
  }
  return entry->parse(fields);
}

/// A one-component section as JSON: its kind and its parameters.
template <class Interface>
nlohmann::json component_json(const Interface& component) {
  nlohmann::json j = {{"kind", std::string(component.kind())}};
  j.update(component.params_json());
  return j;
}

/// The reference of a one-component section: `kind` (default `default_kind`), then every
/// registered kind's own keys, each kind in a table of its own.
template <class Interface>
std::vector<ReferenceRow> component_reference(const std::string& section,
                                              std::string_view default_kind) {
  const auto& registry = ComponentRegistry<Interface>::instance();
  std::vector<std::string> kinds;
  for (const auto* e : registry.entries()) kinds.push_back(e->name);
  std::vector<ReferenceRow> rows = {
      reference_row(section, "kind", FieldKind::kText, "", std::string(default_kind), {}, kinds,
                    fmt::format("the {}'s kind; its own keys follow", Interface::kKindName))};
  for (const auto* entry : registry.entries()) {
    for (ReferenceRow& row : entry->reference(section)) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace edx::arch

/// Registers implementation `Impl` of `Interface` under `name` (a string literal) with a one-line
/// `doc`, in the implementation's own file. The static lives in that translation unit; the
/// library holding it is linked whole (cmake: edx_link_whole) so that the linker keeps it.
#define EDX_REGISTER_COMPONENT(Interface, Impl, name, doc)       \
  [[maybe_unused]] static const bool edx_registered_##Impl =     \
      ::edx::arch::ComponentRegistry<Interface>::instance().add( \
          ::edx::arch::component_entry<Interface, Impl>(name, doc))
