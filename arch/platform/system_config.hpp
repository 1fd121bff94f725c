#pragma once
// The `system:` section of a platform (docs/CONFIG.md): how frames arrive and queue in the
// whole-system DES (arch/system/system_des.hpp, docs/MODEL.md "System DES").
#include <nlohmann/json.hpp>
#include <string>

#include "common/config_fields.hpp"

namespace YAML {
class Node;
}

namespace edx::arch {

/// What happens to a frame that arrives while the camera queue is full.
enum class DropPolicy {
  kOldest,  ///< the oldest waiting frame is dropped, the new one queued (fresh data first)
  kNewest,  ///< the arriving frame is dropped
  kNone,    ///< nothing is dropped: the queue grows without bound
};
const char* to_string(DropPolicy policy);
/// "oldest" | "newest" | "none"; throws std::runtime_error otherwise.
DropPolicy parse_drop_policy(const std::string& text);

/// `system:` section of a platform.
struct SystemConfig {
  /// Camera frame rate of the streamed run; 0: frames back to back (the next frame is there
  /// when the frontend can take it; the paper's throughput figures).
  double sensor_fps = 0;
  /// Frames waiting for the frontend (with sensor_fps > 0); a full queue drops by `drop`.
  int queue_depth = 2;
  DropPolicy drop = DropPolicy::kOldest;
  /// Frontend results waiting for the backend thread; a full queue stalls the frontend
  /// (back-pressure: the frame keeps its frame buffer until its results are queued).
  int results_queue_depth = 2;
  /// false: no contention (idle link per transfer, analytical kernel times, unbounded queues):
  /// the analytical model, for cross-checking.
  bool contention = true;

  /// Every key of `system:` (docs/CONFIG.md).
  static const FieldList<SystemConfig>& fields();
  void validate() const;  ///< throws std::runtime_error naming the field
  nlohmann::json to_json() const;
  /// Reads a `system:` map over the defaults; errors name file, line and key.
  static SystemConfig from_yaml(const YAML::Node& node, const std::string& where);
};

}  // namespace edx::arch
