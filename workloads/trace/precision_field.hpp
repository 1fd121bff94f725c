#pragma once
// The `precision` key of an options struct or a platform section (fp64|fp32), one definition for
// the workload's backends and the platform's units (docs/TRACE.md, meta precision).
#include <string>
#include <utility>

#include "common/config_fields.hpp"
#include "workloads/trace/records.hpp"

namespace edx::trace {

template <class Config>
Field<Config> precision_field(Precision Config::*member, std::string doc) {
  return enum_field(
      "precision", member, {"fp64", "fp32"}, [](Precision p) { return to_string(p); },
      [](const std::string& text) { return parse_precision(text); }, std::move(doc));
}

}  // namespace edx::trace
