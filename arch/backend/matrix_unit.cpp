#include "arch/backend/matrix_unit.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "arch/common/bounds.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {

std::int64_t MatrixUnit::batch_cycles(const trace::OpRecord& op, int copies,
                                      const BackendConfig& backend) const {
  const std::int64_t shared = cycles(op, copies, backend);
  const std::int64_t rounds = (op.batch + std::max(1, copies) - 1) / std::max(1, copies);
  return std::min(op.batch * shared, rounds * cycles(op, 1, backend));
}

cost::Resources factorization_datapath(double lanes, cost::Arithmetic arithmetic) {
  cost::Datapath d;
  d.macs(lanes, arithmetic).sqrt(1, arithmetic).divider(1, arithmetic);
  d.registers(2.0 * lanes * cost::word_bits(arithmetic));
  cost::address_generator(d);
  return d.resources();
}

cost::Arithmetic MatrixUnitInstance::arithmetic() const {
  return precision == trace::Precision::kFp32 ? cost::Arithmetic::kSingle
                                              : cost::Arithmetic::kDouble;
}

const FieldList<MatrixUnitInstance>& MatrixUnitInstance::fields() {
  using C = MatrixUnitInstance;
  static const FieldList<C> list = {
      field("count", &C::count, "",
            "identical copies sharing the unit's ops and their work; 0 leaves it out (its ops "
            "stay on the host)",
            Bounds::at_least(0).at_most(1024)),
      field("clock_mhz", &C::clock_mhz, "MHz", "the unit's clock; 0: the backend's clock_mhz",
            Bounds::at_least(0).at_most(1000))
          .expects(bounds::kUnitClockExpected),
  };
  return list;
}

nlohmann::json MatrixUnitInstance::to_json() const { return instance_json(*this); }

MatrixUnitInstance make_matrix_unit(std::string name, std::string_view kind, int count) {
  MatrixUnitInstance m;
  m.name = std::move(name);
  m.unit = ComponentRegistry<MatrixUnit>::instance().make(kind);
  m.count = count;
  return m;
}

MatrixUnitInstance make_matrix_unit(std::string name, std::string_view kind,
                                    const std::string& params, int count) {
  MatrixUnitInstance m = make_matrix_unit(name, kind, count);
  YamlFields fields(YAML::Load(params), "code", "backend.units." + name);
  m.unit = ComponentRegistry<MatrixUnit>::instance().at(kind).parse(fields);
  return m;
}

}  // namespace edx::arch
