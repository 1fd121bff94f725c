#include "arch/host/host_processor.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "common/config_fields.hpp"
#include "common/input_error.hpp"
#include "common/resources.hpp"
#include "common/yaml_fields.hpp"
#include "workloads/trace/host_speed.hpp"

namespace edx::arch {

const FieldList<HostPower>& HostPower::fields() {
  using C = HostPower;
  static const FieldList<C> list = {
      field("active_w", &C::active_w, "W", "package power while any core computes",
            Bounds::at_least(0)),
      field("idle_w", &C::idle_w, "W", "package power while every core waits (<= active_w)",
            Bounds::at_least(0)),
  };
  return list;
}

void HostPower::validate() const {
  check_fields(*this, "host", fields());
  require_field(idle_w <= active_w, "host", "idle_w", "a power in [0, active_w] W");
}

const FieldList<SuiteTimeKeys>& SuiteTimeKeys::fields() {
  using C = SuiteTimeKeys;
  // At most 100 s: 236 times the Kaby Lake anchor's 423 ms (a 100 MHz in-order core), and host
  // times scale with it: the simulated 2^64 ps still hold about 10^5 frames of 1280x720 work.
  const Bounds suite_ms = Bounds::at_least(0).at_most(1e5);
  static const FieldList<C> list = {
      field("suite", &C::suite, "",
            "reference-suite version the suite times are for (a trace's must match)",
            Bounds::at_least(1).at_most(trace::kHostSpeedSuite))
          .expects(fmt::format("{} (the reference-suite version edx host-speed measures)",
                               trace::kHostSpeedSuite)),
      field("frontend_suite_ms", &C::frontend_suite_ms, "ms",
            "the reference suite's frontend part on this host, CPU time (suite_scaled: 0 with "
            "backend_suite_ms 0, the trace host is the target; datasheet: 0 on a processor "
            "predicted from its `reference`)",
            suite_ms),
      field("provenance", &C::provenance, "", "where frontend_suite_ms comes from"),
      field("backend_suite_ms", &C::backend_suite_ms, "ms",
            "the reference suite's backend part on this host, CPU time", suite_ms),
      field("backend_provenance", &C::backend_provenance, "", "where backend_suite_ms comes from"),
      enum_field(
          "times", &C::times, {"modeled", "measured"},
          [](HostTimeSource t) { return std::string(to_string(t)); },
          [](const std::string& text) { return parse_host_times(text); },
          "host times from the op-count model of the trace's work (modeled: the same on any "
          "tracing machine) or the trace's measured CPU times (measured); either is mapped by "
          "the suite times"),
  };
  return list;
}

SuiteTimes SuiteTimeKeys::suite_times(const std::string& name) const {
  return {name, suite, frontend_suite_ms, backend_suite_ms, provenance, backend_provenance};
}

std::string bundled_description_file(const std::string& dir, const std::string& what,
                                     const std::string& name) {
  const std::filesystem::path path = common::find_resource(dir);
  std::vector<std::string> known;  // sorted: the message is the same on every machine
  for (const auto& entry : std::filesystem::directory_iterator(path)) {
    if (entry.path().extension() != ".yaml") continue;
    if (entry.path().stem().string() == name) return entry.path().string();
    known.push_back(entry.path().stem().string());
  }
  std::sort(known.begin(), known.end());
  throw InputError::expected("", fmt::format("a bundled {} ({})", what, fmt::join(known, ", ")),
                             name);
}

std::shared_ptr<const HostProcessor> make_host_processor(std::string_view kind,
                                                         const std::string& params) {
  YamlFields fields(YAML::Load(params), "code", "host");
  return ComponentRegistry<HostProcessor>::instance().at(kind).parse(fields);
}

}  // namespace edx::arch
