#include "arch/backend/backend_config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "arch/common/bounds.hpp"
#include "common/yaml_fields.hpp"
#include "workloads/trace/precision_field.hpp"

namespace edx::arch {
namespace {

/// Keys of `backend:` before the units were instances (2026-11-28): where each went.
const std::map<std::string, std::string>& moved_keys() {
  static const std::map<std::string, std::string> moved = {
      {"gemm_block", "backend.units.<name>.block of a systolic_array unit"},
      {"gemm_overlap_tiles", "backend.units.<name>.overlap_tiles of a systolic_array unit"},
      {"decomp_block", "backend.units.<name>.block of a decomposition unit"},
      {"inverse_lanes", "backend.units.<name>.lanes of an inverse unit"},
      {"structured_inverse", "backend.units.<name>.structured of an inverse unit"},
      {"transpose_words_per_cycle", "backend.units.<name>.words_per_cycle of a transpose unit"},
      {"trsv_lanes", "backend.units.<name>.lanes of a substitution unit"},
      {"blocked_solvers",
       "backend.units.<name>.blocked of the decomposition and substitution units"},
      {"divide_latency_cycles",
       "backend.units.<name>.divide_latency_cycles of the decomposition, inverse and substitution "
       "units"},
      {"sqrt_latency_cycles", "backend.units.<name>.sqrt_latency_cycles of a decomposition unit"},
      {"scalar_bytes", "backend.precision (fp64: 8 bytes a scalar, fp32: 4)"},
  };
  return moved;
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
            bounds::clock_mhz()),
      trace::precision_field(
          &C::precision,
          "the units' arithmetic (MACs, dividers, roots) and a matrix element in "
          "the SPM and on the link (fp64: 8 bytes, fp32: 4); must be the "
          "trace's"),
      // At most 1 GiB: 20 times the on-chip memory of the largest FPGAs (a VU19P's BRAM and
      // URAM, 54 MB); the BRAM mapping counts its words in 64 bits.
      field("spm_bytes", &C::spm_bytes, "bytes", "the scratchpad holding the running op's operands",
            Bounds::at_least(1).at_most(1 << 30)),
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
      throw InputError({}, "backend.units." + u.name, "no unit kind");
    }
    check_fields(u, "backend.units." + u.name, MatrixUnitInstance::fields());
    require_field(bounds::unit_clock_ok(u.clock_mhz), "backend.units." + u.name, "clock_mhz",
                  bounds::kUnitClockExpected, fmt::format("{}", u.clock_mhz));
  }
  // Every op has one server at most (an op's unit is the one place its cycles come from).
  for (trace::Op op : trace::kOps) {
    const MatrixUnitInstance* first = nullptr;
    for (const MatrixUnitInstance& u : units) {
      if (u.count == 0 || !u.unit->serves(op)) continue;
      if (first != nullptr) {
        throw InputError({}, "backend.units." + u.name,
                         fmt::format("expected one unit per op, but {} serves {} too (count: 0 "
                                     "leaves a unit out)",
                                     first->name, trace::to_string(op)));
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

BackendConfig BackendConfig::parse(YamlFields& yaml) {
  BackendConfig config;
  yaml.refuse_moved(moved_keys());
  parse_fields(yaml, config, fields());
  const YAML::Node units = yaml.take("units");
  const auto precision = [&](MatrixUnitInstance& unit) { unit.precision = config.precision; };
  for (MatrixUnitInstance& unit : config.units) precision(unit);
  if (units) {
    if (!units.IsMap()) yaml.fail("units", "expected a map of named units");
    parse_instances<MatrixUnit>(units, yaml.where(), yaml.prefix() + ".units", config.units,
                                precision);
  }
  return config;
}

std::vector<ReferenceRow> BackendConfig::reference(const std::string& section,
                                                   const std::string& heading) {
  std::vector<ReferenceRow> rows = reference_rows(section, fields(), BackendConfig{}, heading);
  rows.push_back(reference_row(section, "units", FieldKind::kText, "",
                               std::string("the five units of Table II"), {}, {},
                               "the matrix units, a map of named instances (below)"));
  rows.back().group = heading;
  for (ReferenceRow& row : instance_reference<MatrixUnit, MatrixUnitInstance>(
           section + ".units", "<name>",
           "gemm: systolic_array, decomposition, inverse, transpose, substitution")) {
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace edx::arch
