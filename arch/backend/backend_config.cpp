#include "arch/backend/backend_config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "arch/common/yaml_fields.hpp"

namespace edx::arch {
namespace {

/// Keys of `backend:` before the units were instances (2026-11-28): where each went.
const std::map<std::string, std::string>& moved_keys() {
  static const std::map<std::string, std::string> moved = {
      {"gemm_block", "units.<name>.block of a systolic_array unit"},
      {"gemm_overlap_tiles", "units.<name>.overlap_tiles of a systolic_array unit"},
      {"decomp_block", "units.<name>.block of a decomposition unit"},
      {"inverse_lanes", "units.<name>.lanes of an inverse unit"},
      {"structured_inverse", "units.<name>.structured of an inverse unit"},
      {"transpose_words_per_cycle", "units.<name>.words_per_cycle of a transpose unit"},
      {"trsv_lanes", "units.<name>.lanes of a substitution unit"},
      {"blocked_solvers", "units.<name>.blocked of the decomposition and substitution units"},
      {"divide_latency_cycles",
       "units.<name>.divide_latency_cycles of the decomposition, inverse and substitution units"},
      {"sqrt_latency_cycles", "units.<name>.sqrt_latency_cycles of a decomposition unit"},
  };
  return moved;
}

/// One `backend.units.<name>` map: its kind (`default_kind` when it names a default unit and
/// gives none), the instance keys, then the kind's own keys over their defaults.
MatrixUnitInstance parse_unit(const std::string& name, const YAML::Node& node,
                              const std::string& where, const std::string& prefix, int scalar_bytes,
                              std::string_view default_kind) {
  YamlFields fields(node, where, prefix + "." + name);
  const YAML::Node kind = fields.take("kind");
  const auto& registry = ComponentRegistry<MatrixUnit>::instance();
  if ((!kind && default_kind.empty()) || (kind && !kind.IsScalar())) {
    fields.fail("kind", fmt::format("required for a unit not among the defaults: one of {}",
                                    registry.names()));
  }
  const std::string kind_name = kind ? kind.Scalar() : std::string(default_kind);
  const ComponentEntry<MatrixUnit>* entry = registry.find(kind_name);
  if (entry == nullptr) {
    fields.fail("kind", fmt::format("expected one of {}, got '{}'", registry.names(), kind_name));
  }
  MatrixUnitInstance unit;
  unit.name = name;
  unit.precision = scalar_bytes == 4 ? "single" : "double";
  parse_fields(fields, unit, MatrixUnitInstance::fields());
  unit.unit = entry->parse(fields);  // the kind's keys; unknown keys refused there
  return unit;
}

}  // namespace

std::vector<MatrixUnitInstance> BackendConfig::paper_backend_units() {
  return {make_matrix_unit("gemm", "systolic_array"),
          make_matrix_unit("decomposition", "decomposition"),
          make_matrix_unit("inverse", "inverse"), make_matrix_unit("transpose", "transpose"),
          make_matrix_unit("substitution", "substitution")};
}

const MatrixUnitInstance* BackendConfig::unit_for(trace::Op op) const {
  for (const MatrixUnitInstance& u : units) {
    if (u.count > 0 && u.unit->serves(op)) return &u;
  }
  return nullptr;
}

double BackendConfig::clock_of(const MatrixUnitInstance& unit) const {
  return unit.clock_mhz > 0 ? unit.clock_mhz : clock_mhz;
}

const FieldList<BackendConfig>& BackendConfig::fields() {
  using C = BackendConfig;
  const Bounds positive = Bounds::at_least(1);
  static const FieldList<C> list = {
      field("clock_mhz", &C::clock_mhz, "MHz",
            "the units' clock unless a unit sets its own (assumed: the frontend's HLS clock)",
            Bounds::above(0).at_most(1000)),
      choice_field("scalar_bytes", &C::scalar_bytes, "bytes", {"4", "8"},
                   "one matrix element in the SPM and on the link: 8 double, 4 single (also the "
                   "units' default precision)"),
      field("spm_bytes", &C::spm_bytes, "bytes", "the scratchpad holding the running op's operands",
            positive),
      field("symmetric_optimization", &C::symmetric_optimization, "",
            "compute and store only one triangle of symmetric results (Sec. VI-A)"),
      field("pose_dim", &C::pose_dim, "",
            "p: pose parameters of a marginalized keyframe, where the trace does not say",
            positive),
      field("landmark_dim", &C::landmark_dim, "",
            "l: parameters per marginalized landmark, where the trace does not say", positive),
  };
  return list;
}

void BackendConfig::validate() const {
  check_fields(*this, "backend", fields());
  for (const MatrixUnitInstance& u : units) {
    if (u.unit == nullptr) {
      throw std::runtime_error(fmt::format("backend.units.{}: no unit kind", u.name));
    }
    check_fields(u, "backend.units." + u.name, MatrixUnitInstance::fields());
  }
  // Every op has one server at most (an op's unit is the one place its cycles come from).
  for (trace::Op op : trace::kOps) {
    const MatrixUnitInstance* first = nullptr;
    for (const MatrixUnitInstance& u : units) {
      if (u.count == 0 || !u.unit->serves(op)) continue;
      if (first != nullptr) {
        throw std::runtime_error(fmt::format(
            "backend.units.{}: expected one unit per op, but {} serves {} too (count: 0 leaves "
            "a unit out)",
            u.name, first->name, trace::to_string(op)));
      }
      first = &u;
    }
  }
}

nlohmann::json BackendConfig::to_json() const {
  nlohmann::json j = fields_to_json(*this, fields());
  nlohmann::json list = nlohmann::json::object();
  for (const MatrixUnitInstance& u : units) list[u.name] = u.to_json();
  j["units"] = list;
  return j;
}

BackendConfig BackendConfig::from_yaml(const YAML::Node& node, const std::string& where,
                                       const std::string& prefix) {
  BackendConfig config;
  YamlFields yaml(node, where, prefix);
  for (const auto& [key, now] : moved_keys()) {
    if (node && node.IsMap() && node[key]) {
      yaml.fail(key, fmt::format("moved: now {}.{} (docs/CONFIG.md)", prefix, now));
    }
  }
  parse_fields(yaml, config, fields());
  const YAML::Node units = yaml.take("units");
  yaml.finish();
  for (MatrixUnitInstance& unit : config.units) {
    unit.precision = config.scalar_bytes == 4 ? "single" : "double";
  }
  if (units) {
    if (!units.IsMap()) yaml.fail("units", "expected a map of named units");
    // The default units are the implicit parent: a listed name among them overrides it (its
    // kind kept unless given), a new name adds a unit, count: 0 leaves one out.
    for (const auto& item : units) {
      const std::string name = item.first.Scalar();
      const auto it = std::find_if(config.units.begin(), config.units.end(),
                                   [&](const MatrixUnitInstance& u) { return u.name == name; });
      const std::string_view default_kind =
          it != config.units.end() ? it->unit->kind() : std::string_view();
      MatrixUnitInstance unit = parse_unit(name, item.second, where, prefix + ".units",
                                           config.scalar_bytes, default_kind);
      if (it != config.units.end()) {
        *it = std::move(unit);
      } else {
        config.units.push_back(std::move(unit));
      }
    }
  }
  validate_at(yaml, [&config] { config.validate(); });
  return config;
}

std::vector<ReferenceRow> BackendConfig::reference() {
  std::vector<ReferenceRow> rows = reference_rows("backend", fields());
  rows.push_back(reference_row("backend", "units", FieldKind::kText, "",
                               std::string("the five units of Table II"), {}, {},
                               "the matrix units, a map of named instances (below)"));
  rows.push_back(reference_row(
      "backend.units.<name>", "kind", FieldKind::kText, "", std::string(), {},
      [] {
        std::vector<std::string> kinds;
        for (const auto* e : ComponentRegistry<MatrixUnit>::instance().entries()) {
          kinds.push_back(e->name);
        }
        return kinds;
      }(),
      "the unit's kind: required for a unit not among the defaults, which keep "
      "theirs (gemm: systolic_array, decomposition, inverse, transpose, "
      "substitution); its own keys follow"));
  for (const ReferenceRow& row :
       reference_rows("backend.units.<name>", MatrixUnitInstance::fields())) {
    rows.push_back(row);
  }
  for (const auto* entry : ComponentRegistry<MatrixUnit>::instance().entries()) {
    for (ReferenceRow row : entry->reference("backend.units.<name>"))
      rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace edx::arch
