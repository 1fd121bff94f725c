#pragma once
// The ATE a localization run reports per mode (docs/EVAL.md "ATE of a run"): each (segment,
// mode) of a run, the poses that mode estimated on that segment against the ground truth at the
// same frame times, aligned on their own (a segment's mode starts its own world frame, and a mix
// jumps from world to world at a segment boundary), then pooled over segments:
//
//   ATE RMSE(mode) = sqrt( sum_s pairs_s rmse_s^2 / sum_s pairs_s )
//
// with rmse_s the ATE RMSE of segment s after its alignment. The one definition the pipeline's
// runs (mix_runner: `edx trace --mix`, `edx characterize`) and the sweeps' accuracy metrics
// (trace_accuracy.hpp, read back from a trace) use.
#include <cstddef>
#include <optional>

#include "workloads/eval/evaluate.hpp"

namespace edx::eval {

/// The alignment of a run's segment: position + yaw (4 DoF) when the run had an IMU (gravity
/// makes roll and pitch observable), else SE(3).
AlignmentMethod segment_alignment(bool has_imu);

/// The ATE of one (segment, mode): `estimate` against `truth`, both stamped with frame times (s),
/// associated within 1 ms and aligned by `alignment`. None with fewer estimates than the
/// alignment needs (min_pairs_for).
std::optional<EvalResult> segment_ate(const Trajectory& truth, const Trajectory& estimate,
                                      AlignmentMethod alignment);

/// ATE RMSE pooled over segments (above).
struct PooledAte {
  double squared_error_sum = 0;  ///< sum over segments of pairs * rmse^2
  std::size_t pairs = 0;
  std::size_t segments = 0;
  void add(const EvalResult& segment);
  /// None when no segment had enough estimates.
  std::optional<double> rmse() const;
};

}  // namespace edx::eval
