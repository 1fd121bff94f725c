#include "workloads/eval/evaluate.hpp"

#include <fmt/core.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include "workloads/eval/association.hpp"

namespace edx::eval {
namespace {

/// Associated poses ready for the metrics: gt[i] and est[i] belong together. `track_gt` and
/// `track_est` are the ground-truth track the KITTI segments run along, with the estimate (if
/// any) at each of its frames.
struct PreparedPoses {
  std::vector<Pose> gt;
  std::vector<Pose> est;
  std::vector<std::int64_t> est_frame_index;
  std::vector<Pose> track_gt;
  std::vector<std::optional<Pose>> track_est;
  std::size_t est_unmatched = 0;
};

/// edx conventions: poses as in the files; segments along the associated pairs only.
PreparedPoses prepare_edx(const Trajectory& gt, const Trajectory& est, double t_max_diff_s) {
  const Association association = associate(gt, est, t_max_diff_s);
  PreparedPoses prepared;
  prepared.est_unmatched = association.est_unmatched;
  for (const auto& pair : association.pairs) {
    prepared.gt.push_back(gt.poses[pair.gt].pose);
    prepared.est.push_back(est.poses[pair.est].pose);
    prepared.est_frame_index.push_back(est.poses[pair.est].frame_index);
  }
  return prepared;
}

/// kitti-odom-eval conventions: with k0 the first estimated frame, every estimated pose becomes
/// E_k0^-1 E_k and the ground truth of every estimated frame G_k0^-1 G_k; ground-truth frames
/// without an estimate keep their original pose (as the tool does), which matters only for the
/// path distances of the segment search.
PreparedPoses prepare_kitti_odom_eval(const Trajectory& gt, const Trajectory& est) {
  if (gt.stamp_kind != StampKind::kFrameIndex || est.stamp_kind != StampKind::kFrameIndex) {
    throw std::runtime_error(
        "the kitti-odom-eval conventions need frame-indexed (kitti format) trajectories");
  }
  // Position in gt of every estimated frame; the tool cannot evaluate frames without ground truth.
  std::vector<std::size_t> gt_position(est.poses.size());
  std::size_t g = 0;
  for (std::size_t e = 0; e < est.poses.size(); ++e) {
    const auto index = est.poses[e].frame_index;
    while (g < gt.poses.size() && gt.poses[g].frame_index < index) ++g;
    if (g == gt.poses.size() || gt.poses[g].frame_index != index) {
      throw std::runtime_error(fmt::format("{}:{}: frame {} has no ground-truth pose in {}",
                                           est.source, est.poses[e].line, index, gt.source));
    }
    gt_position[e] = g;
  }

  PreparedPoses prepared;
  prepared.track_gt.reserve(gt.poses.size());
  for (const auto& stamped : gt.poses) prepared.track_gt.push_back(stamped.pose);
  prepared.track_est.assign(gt.poses.size(), std::nullopt);

  const Pose est_origin_inverse = est.poses.front().pose.inverse();
  const Pose gt_origin_inverse = gt.poses[gt_position.front()].pose.inverse();
  for (std::size_t e = 0; e < est.poses.size(); ++e) {
    const std::size_t p = gt_position[e];
    prepared.track_gt[p] = gt_origin_inverse * gt.poses[p].pose;
    prepared.track_est[p] = est_origin_inverse * est.poses[e].pose;
    prepared.gt.push_back(prepared.track_gt[p]);
    prepared.est.push_back(*prepared.track_est[p]);
    prepared.est_frame_index.push_back(est.poses[e].frame_index);
  }
  return prepared;
}

Eigen::Matrix3Xd positions(const std::vector<Pose>& poses) {
  Eigen::Matrix3Xd matrix(3, static_cast<Eigen::Index>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    matrix.col(static_cast<Eigen::Index>(i)) = poses[i].translation();
  }
  return matrix;
}

}  // namespace

EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options) {
  if (gt.poses.empty() || est.poses.empty()) {
    throw std::runtime_error(
        fmt::format("{}: no poses", gt.poses.empty() ? gt.source : est.source));
  }
  if (!(options.rpe_delta_m > 0.0)) {
    throw std::runtime_error(
        fmt::format("rpe_delta_m must be a positive distance, got {}", options.rpe_delta_m));
  }
  PreparedPoses prepared = options.kitti_odom_eval ? prepare_kitti_odom_eval(gt, est)
                                                   : prepare_edx(gt, est, options.t_max_diff_s);

  EvalResult result;
  result.gt_poses = gt.poses.size();
  result.est_poses = est.poses.size();
  result.pairs = prepared.gt.size();
  result.est_unmatched = prepared.est_unmatched;
  result.alignment = options.alignment;
  result.kitti_odom_eval = options.kitti_odom_eval;

  // Align the estimate onto the ground truth; every metric sees the aligned estimate.
  if (prepared.gt.size() < min_pairs_for(options.alignment)) {
    throw std::runtime_error(fmt::format(
        "{} and {} share only {} pose pair(s): too few for {} alignment (need at least {})",
        gt.source, est.source, prepared.gt.size(), alignment_method_name(options.alignment),
        min_pairs_for(options.alignment)));
  }
  result.align =
      align_positions(positions(prepared.est), positions(prepared.gt), options.alignment);
  for (auto& pose : prepared.est) pose = result.align.apply(pose);
  for (auto& pose : prepared.track_est) {
    if (pose) pose = result.align.apply(*pose);
  }
  if (!options.kitti_odom_eval) {  // edx: segments run along the associated pairs
    prepared.track_gt = prepared.gt;
    prepared.track_est.assign(prepared.est.begin(), prepared.est.end());
  }

  result.ate_m = summarize_errors(position_errors(prepared.gt, prepared.est));

  // Consecutive pairs: adjacent associated pairs (edx); frames k and k+1 (kitti-odom-eval).
  std::vector<FramePair> consecutive = consecutive_pairs(prepared.gt.size());
  if (options.kitti_odom_eval) {
    std::erase_if(consecutive, [&](const FramePair& pair) {
      return prepared.est_frame_index[pair.second] != prepared.est_frame_index[pair.first] + 1;
    });
  }
  const RelativeErrors rpe = relative_errors(prepared.gt, prepared.est, consecutive);
  result.rpe_trans_m = rpe.translation_m;
  result.rpe_rot_deg = rpe.rotation_deg;

  const std::vector<double> distances = path_distances(prepared.gt);
  result.gt_length_m = distances.back();
  result.rpe_delta_m = options.rpe_delta_m;
  const RelativeErrors rpe_delta =
      relative_errors(prepared.gt, prepared.est, pairs_at_distance(distances, options.rpe_delta_m));
  result.rpe_delta_trans_m = rpe_delta.translation_m;
  result.rpe_delta_rot_deg = rpe_delta.rotation_deg;

  result.kitti = summarize_kitti_segments(
      kitti_segment_errors(prepared.track_gt, prepared.track_est, options.segments),
      options.segments);
  return result;
}

}  // namespace edx::eval
