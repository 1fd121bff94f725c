#include "workloads/eval/segment_ate.hpp"

#include <cmath>

namespace edx::eval {

AlignmentMethod segment_alignment(bool has_imu) {
  return has_imu ? AlignmentMethod::kPosYaw : AlignmentMethod::kSe3;
}

std::optional<EvalResult> segment_ate(const Trajectory& truth, const Trajectory& estimate,
                                      AlignmentMethod alignment) {
  EvalOptions options;
  options.alignment = alignment;
  options.t_max_diff_s = 1e-3;  // both sides are stamped with the frame times
  if (estimate.poses.size() < min_pairs_for(alignment) || truth.poses.empty()) return std::nullopt;
  return evaluate(truth, estimate, options);
}

void PooledAte::add(const EvalResult& segment) {
  squared_error_sum += static_cast<double>(segment.pairs) * segment.ate_m.rmse * segment.ate_m.rmse;
  pairs += segment.pairs;
  ++segments;
}

std::optional<double> PooledAte::rmse() const {
  if (pairs == 0) return std::nullopt;
  return std::sqrt(squared_error_sum / static_cast<double>(pairs));
}

}  // namespace edx::eval
