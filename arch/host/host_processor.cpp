#include "arch/host/host_processor.hpp"

#include <yaml-cpp/yaml.h>

#include "common/yaml_fields.hpp"

namespace edx::arch {

std::shared_ptr<const HostProcessor> make_host_processor(std::string_view kind,
                                                         const std::string& params) {
  YamlFields fields(YAML::Load(params), "code", "host");
  return ComponentRegistry<HostProcessor>::instance().at(kind).parse(fields);
}

}  // namespace edx::arch
