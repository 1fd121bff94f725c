#pragma once
// Association of estimated poses with ground-truth poses: by frame index (KITTI) or by nearest
// timestamp within a tolerance (TUM, EuRoC).
#include <cstddef>
#include <vector>

#include "workloads/eval/trajectory.hpp"

namespace edx::eval {

/// One associated pair: indices into gt.poses and est.poses.
struct PosePair {
  std::size_t gt = 0;
  std::size_t est = 0;
};

struct Association {
  std::vector<PosePair> pairs;    ///< sorted by est index (and so by time)
  std::size_t est_unmatched = 0;  ///< estimated poses left without a ground-truth partner
};

/// Pairs poses with equal frame index. Throws when there is none in common.
Association associate_by_frame_index(const Trajectory& gt, const Trajectory& est);

/// Pairs each estimated pose with the nearest ground-truth pose within `t_max_diff_s` seconds,
/// using every pose at most once. Deterministic: among all candidate pairs with
/// |t_gt - t_est| <= t_max_diff_s, the closest pair is taken first (ties: earlier est, then
/// earlier gt), its two poses are removed, and so on. Throws when the time spans do not overlap
/// or no pair is within tolerance.
Association associate_by_time(const Trajectory& gt, const Trajectory& est, double t_max_diff_s);

/// Frame-index association for kFrameIndex trajectories, time association otherwise. Throws when
/// the two trajectories are stamped differently.
Association associate(const Trajectory& gt, const Trajectory& est, double t_max_diff_s);

}  // namespace edx::eval
