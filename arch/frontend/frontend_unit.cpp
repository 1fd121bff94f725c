#include "arch/frontend/frontend_unit.hpp"

#include <yaml-cpp/yaml.h>

#include "arch/common/bounds.hpp"
#include "common/yaml_fields.hpp"

namespace edx::arch {

const FieldList<FrontendUnitInstance>& FrontendUnitInstance::fields() {
  using C = FrontendUnitInstance;
  static const FieldList<C> list = {
      field("count", &C::count, "",
            "identical copies, a pool the task's runs take first come, first served (2 FD: the "
            "left and right images side by side)",
            Bounds::at_least(1).at_most(64)),
      field("clock_mhz", &C::clock_mhz, "MHz", "the unit's clock; 0: the frontend's clock_mhz",
            Bounds::at_least(0).at_most(1000))
          .expects(bounds::kUnitClockExpected),
  };
  return list;
}

nlohmann::json FrontendUnitInstance::to_json() const { return instance_json(*this); }

FrontendUnitInstance make_frontend_unit(trace::Task task, std::string_view kind,
                                        const std::string& params, int count) {
  FrontendUnitInstance u;
  u.name = trace::to_string(task);
  YamlFields fields(YAML::Load(params), "code", "frontend.units." + u.name);
  u.unit = ComponentRegistry<FrontendUnit>::instance().at(kind).parse(fields);
  u.count = count;
  return u;
}

}  // namespace edx::arch
