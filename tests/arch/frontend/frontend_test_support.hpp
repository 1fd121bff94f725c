#pragma once
// Shared by the frontend tests: setting a unit's parameters in a FrontendConfig built in code.
#include <string>

#include "arch/frontend/frontend_config.hpp"

namespace edx::arch::testing {

/// Replaces the parameters of the unit of `task` by `params` (YAML of its kind's keys, e.g.
/// "{tests_per_cycle: 256}"; keys not given take their defaults), keeping its kind and count.
inline void set_unit(FrontendConfig& config, trace::Task task, const std::string& params) {
  FrontendUnitInstance& u = config.units[static_cast<std::size_t>(task)];
  u = make_frontend_unit(task, u.unit->kind(), params, u.count);
}

}  // namespace edx::arch::testing
