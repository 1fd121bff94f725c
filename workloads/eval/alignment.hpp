#pragma once
// Alignment of an estimated trajectory to the ground truth on associated positions:
//   p_gt ~ s R p_est + t,
// chosen to minimise sum_i |p_gt,i - (s R p_est,i + t)|^2 over the allowed degrees of freedom.
#include <Eigen/Core>
#include <cstddef>
#include <string_view>

#include "workloads/eval/trajectory.hpp"

namespace edx::eval {

enum class AlignmentMethod {
  kNone,    ///< identity
  kSe3,     ///< R, t (Umeyama without scale), 6 DoF
  kSim3,    ///< s, R, t (Umeyama with scale), 7 DoF
  kPosYaw,  ///< t and a rotation about the gravity axis z only, 4 DoF (VIO: roll and pitch are
            ///< observable from gravity, so they are not aligned away)
};

/// "none", "se3", "sim3" or "posyaw"; throws std::runtime_error on anything else.
AlignmentMethod parse_alignment_method(std::string_view name);
std::string_view alignment_method_name(AlignmentMethod method);

/// Fewest position pairs a method accepts: 1 (none), 2 (posyaw), 3 (se3, sim3).
std::size_t min_pairs_for(AlignmentMethod method);

/// x -> s R x + t, applied to positions and poses.
struct SimilarityTransform {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& position) const {
    return rotation * (scale * position) + translation;
  }
  /// [R_p | t_p] -> [R R_p | s R t_p + t]: the body orientation is rotated, not scaled.
  Pose apply(const Pose& pose) const {
    Pose aligned = pose;
    aligned.linear() = rotation * pose.linear();
    aligned.translation() = apply(Eigen::Vector3d(pose.translation()));
    return aligned;
  }
};

/// The transform taking `est` positions (3xN) onto `gt` positions (3xN) in the least-squares
/// sense. se3/sim3: Umeyama (1991) via Eigen::umeyama. posyaw: with centred positions
/// e_i = p_est,i - mean_est, g_i = p_gt,i - mean_gt and C = sum_i e_i g_i^T, the yaw maximising
/// sum_i g_i^T Rz(theta) e_i is theta = atan2(C01 - C10, C00 + C11), t = mean_gt - Rz mean_est.
/// Throws std::runtime_error with fewer than min_pairs_for(method) pairs, or for sim3 when the
/// estimated positions do not move.
SimilarityTransform align_positions(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt,
                                    AlignmentMethod method);

}  // namespace edx::eval
