#pragma once
// The backends `edx trace --backend NAME` can run, by name, with their default options.
#include <string>
#include <string_view>
#include <vector>

#include "workloads/modes/trace_runner.hpp"

namespace edx::modes {

/// Names accepted by backend_factory: "none" first, then every backend built in.
std::vector<std::string> backend_names();

/// The factory of a named backend with default options; "none" gives an empty factory (frontend
/// only). Throws std::runtime_error listing the known names for any other name.
BackendFactory backend_factory(std::string_view name);

}  // namespace edx::modes
