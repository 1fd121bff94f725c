#include "arch/platform/system_config.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "common/yaml_fields.hpp"

namespace edx::arch {

const char* to_string(DropPolicy policy) {
  switch (policy) {
    case DropPolicy::kOldest:
      return "oldest";
    case DropPolicy::kNewest:
      return "newest";
    case DropPolicy::kNone:
      return "none";
  }
  return "oldest";
}

DropPolicy parse_drop_policy(const std::string& text) {
  if (text == "oldest") return DropPolicy::kOldest;
  if (text == "newest") return DropPolicy::kNewest;
  if (text == "none") return DropPolicy::kNone;
  throw std::runtime_error(fmt::format("expected oldest, newest or none, got '{}'", text));
}

namespace {

constexpr double kMinSensorFps = 1e-3;
constexpr const char* kSensorFpsExpected =
    "0 (frames back to back) or a rate in [0.001, 1e+06] frames/s";

}  // namespace

const FieldList<SystemConfig>& SystemConfig::fields() {
  using C = SystemConfig;
  static const FieldList<C> list = {
      field("sensor_fps", &C::sensor_fps, "frames/s",
            "camera frame rate of the streamed run; 0: frames back to back",
            Bounds::at_least(0).at_most(1e6))
          .expects(kSensorFpsExpected),
      field("queue_depth", &C::queue_depth, "frames",
            "frames waiting for the frontend; a full queue drops by `drop`", Bounds::at_least(1)),
      enum_field(
          "drop", &C::drop, {"oldest", "newest", "none"},
          [](DropPolicy p) { return std::string(to_string(p)); }, parse_drop_policy,
          "which frame a full camera queue drops (none: the camera waits)"),
      field("results_queue_depth", &C::results_queue_depth, "frames",
            "frontend results waiting for the backend; a full queue stalls the frontend",
            Bounds::at_least(1)),
      field("contention", &C::contention, "",
            "false: idle link per transfer, analytical kernel times, unbounded queues (the "
            "analytical model)"),
  };
  return list;
}

void SystemConfig::validate() const {
  check_fields(*this, "system", fields());
  // A camera of at least a frame per 1000 s: frame f arrives at f / fps, and 2^64 ps (213 days)
  // then holds 18 000 frames; a longer trace at a slow rate is refused when it is simulated.
  require_field(sensor_fps == 0 || sensor_fps >= kMinSensorFps, "system", "sensor_fps",
                kSensorFpsExpected, fmt::format("{}", sensor_fps));
}

nlohmann::json SystemConfig::to_json() const { return fields_to_json(*this, fields()); }

SystemConfig SystemConfig::from_yaml(const YAML::Node& node, const std::string& where) {
  return parse_section<SystemConfig>(node, where, "system");
}

}  // namespace edx::arch
