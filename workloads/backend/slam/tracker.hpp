#pragma once
// Tracking (paper Sec. IV-A, SLAM mode): every frame's body pose by motion-only optimization
// against the latest local map, the window's landmarks matched to the frame's features by track
// id. Gauss-Newton with the Huber loss on the stereo reprojection errors of world points X:
//   P_b = R^T (X - p),  P_c = R_bc^T (P_b - t_bc),  r = pi(P_c) - z  (and the right image),
//   dP_c/dp = -R_bc^T R^T,  dP_c/dtheta = R_bc^T [P_b]x,   (H + 1e-6 I) dx = -J^T W r,
// then matches off by more than outlier_px are dropped and the pose refined once more. The
// starting pose is the better (more inliers) of the prediction and a RANSAC PnP on the left
// image (pnp_ransac.hpp: EPnP on minimal sets, 100 iterations, outlier_px, confidence 0.99),
// which rejects the wrong LK tracks that would otherwise pull a non-redescending loss.
#include <Eigen/Geometry>
#include <vector>

#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

struct TrackingResult {
  bool ok = false;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  int matches = 0;  ///< features on window landmarks
  int inliers = 0;  ///< within outlier_px after the last refinement
  double rms_px = 0;
  bool used_ransac = false;                 ///< RANSAC PnP gave the starting pose
  std::vector<std::int64_t> inlier_tracks;  ///< track ids of the inlier matches
};

TrackingResult track_frame(const Window& window, const std::vector<frontend::Feature>& features,
                           const Eigen::Isometry3d& initial_T_world_body,
                           const SlamOptions& options);

}  // namespace edx::backend::slam
