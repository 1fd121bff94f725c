#pragma once
// evaluate(gt, est, options): associate, align, and measure a trajectory against ground truth.
// The one entry point the `edx eval` command and the localization backends call.
#include <cstddef>
#include <optional>
#include <string>

#include "workloads/eval/alignment.hpp"
#include "workloads/eval/metrics.hpp"
#include "workloads/eval/trajectory.hpp"

namespace edx::eval {

struct EvalOptions {
  AlignmentMethod alignment = AlignmentMethod::kSe3;
  /// Largest |t_gt - t_est| (s) of an associated pair (timestamped formats only; TUM's default).
  double t_max_diff_s = 0.02;
  /// Path length (m, measured on the ground truth) of the pairs of the distance-based RPE.
  double rpe_delta_m = 100.0;
  /// Reproduce the public kitti-odom-eval tool (eval_odom.py) exactly; see docs/EVAL.md:
  /// both trajectories re-expressed relative to the first estimated frame (ground-truth frames
  /// without an estimate are left as they are), segment distances along the whole ground truth,
  /// RPE over frame pairs (i, i+1) only, and every estimated frame must have ground truth.
  bool kitti_odom_eval = false;
  KittiSegmentOptions segments;
};

struct EvalResult {
  std::size_t gt_poses = 0;
  std::size_t est_poses = 0;
  std::size_t pairs = 0;          ///< associated pose pairs
  std::size_t est_unmatched = 0;  ///< estimated poses without ground truth (left out)
  AlignmentMethod alignment = AlignmentMethod::kSe3;
  bool kitti_odom_eval = false;
  SimilarityTransform align;  ///< est -> gt, applied to the estimate before every metric
  double gt_length_m = 0.0;   ///< path length of the associated ground truth

  ErrorStats ate_m;  ///< absolute position errors after alignment; ATE RMSE = ate_m.rmse

  ErrorStats rpe_trans_m;  ///< consecutive pairs; the headline figure is the mean
  ErrorStats rpe_rot_deg;  ///< consecutive pairs; the headline figure is the mean
  double rpe_delta_m = 0.0;
  ErrorStats rpe_delta_trans_m;  ///< pairs rpe_delta_m apart along the ground truth
  ErrorStats rpe_delta_rot_deg;

  KittiSummary kitti;  ///< segment errors, 100..800 m
};

/// Associates est with gt (frame index or time), aligns it (options.alignment) and computes every
/// metric. Throws std::runtime_error naming the file on bad input: no association, too few pairs
/// for the alignment, mixed stamp kinds, or (kitti_odom_eval) an estimated frame without ground
/// truth.
EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options = {});

}  // namespace edx::eval
