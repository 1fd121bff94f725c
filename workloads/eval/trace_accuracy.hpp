#pragma once
// The accuracy of a trace, per backend mode, from what it recorded per frame (docs/EVAL.md "ATE
// of a run"): each frame's estimated and ground-truth pose, its time stamp and its mode. The
// frames are cut into the run's segments (a mix trace's `pipeline_params.segments`, in order, by
// their frame counts; otherwise where the sequence changes or time does not increase), and the
// ATE of each (segment, mode) pooled per mode exactly as the pipeline does when it runs
// (segment_ate.hpp), so a sweep's `ate_rmse_vio` is the `edx trace --mix` summary's VIO ATE.
// Alignment: position + yaw, except on KITTI traces (`dataset: kitti:...`, no IMU): SE(3).
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "workloads/eval/segment_ate.hpp"
#include "workloads/trace/records.hpp"

namespace edx::eval {

struct TraceAccuracy {
  AlignmentMethod alignment = AlignmentMethod::kPosYaw;
  std::size_t segments = 0;
  /// Per mode that ran ("registration", "vio", "slam"), pooled over its segments; a mode whose
  /// segments all had too few estimates has no RMSE.
  std::map<std::string, PooledAte> modes;
  /// Over every (segment, mode), pooled the same way: the run's ATE over all its estimates.
  PooledAte all;
  /// {"alignment": "posyaw", "segments": 4, "all": {"ate_rmse_m": x|null, "pairs": n},
  ///  "vio": {...}, ...}
  nlohmann::json to_json() const;
};

/// The alignment of a trace's segments (above).
AlignmentMethod trace_alignment(const trace::TraceMeta& meta);

/// The accuracy of a trace's frames (in trace order) with its meta.
TraceAccuracy trace_accuracy(const std::vector<trace::FrameTrace>& frames,
                             const trace::TraceMeta& meta);

}  // namespace edx::eval
