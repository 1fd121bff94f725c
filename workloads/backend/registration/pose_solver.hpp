#pragma once
// The geometric pieces of registration (paper Sec. IV-A "Tracking", Table I): the projection of
// map points with the camera matrix, RANSAC PnP and the motion-only pose refinement. Poses are
// T_cam_world (p_cam = R p_world + t) of the rectified left camera.
//
// Projection (the accelerable kernel): with C = K [R | t] the 3x4 camera matrix and X the 4xM
// homogeneous map points, Y = C X (3xM, one gemm m = 3, n = M, k = 4); a point projects to
// (u, v) = (Y_0 / Y_2, Y_1 / Y_2) at depth Y_2 (K's last row is [0 0 1]).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "workloads/backend/backend.hpp"
#include "workloads/backend/registration/registration_options.hpp"

namespace edx::backend::registration {

/// C = K [R | t], K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]].
Eigen::Matrix<double, 3, 4> camera_matrix(const BackendCamera& camera,
                                          const Eigen::Isometry3d& T_cam_world);

/// Y = C X: pixel coordinates times depth (rows 0, 1) and depth (row 2) of every column of X,
/// computed at `precision` (fp32: C and X rounded to single, the product in single, Y widened).
Eigen::Matrix3Xd project(const Eigen::Matrix<double, 3, 4>& C, const Eigen::Matrix4Xd& X,
                         trace::Precision precision = trace::Precision::kFp64);

/// A 2D-3D match: a world point and the left-image pixel it was matched to.
struct Correspondence {
  Eigen::Vector3d world = Eigen::Vector3d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double sigma_px = 1;       ///< pixel noise (octave_scale^octave)
  std::size_t landmark = 0;  ///< index of the map point
  std::size_t feature = 0;   ///< index of the frame feature
};

struct PnpResult {
  bool ok = false;
  Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();
  std::vector<std::size_t> inliers;  ///< indices into the correspondences
};

/// RANSAC PnP (pnp_ransac.hpp: EPnP on minimal sets, options.pnp_iterations and
/// pnp_confidence) on the correspondences; ok when at least options.pnp_min_inliers agree within
/// options.pnp_reprojection_px and the pose is finite. Fewer than 4 correspondences or a solver
/// failure: not ok.
PnpResult solve_pnp_ransac(const BackendCamera& camera,
                           const std::vector<Correspondence>& correspondences,
                           const RegistrationOptions& options);

struct RefinementResult {
  Eigen::Isometry3d T_cam_world = Eigen::Isometry3d::Identity();
  std::vector<bool> inlier;  ///< per correspondence, after the last round
  int inliers = 0;
  double rms_px = 0;  ///< RMS reprojection error of the inliers, px
  int iterations = 0;
};

/// Motion-only refinement (ORB-SLAM's pose optimization, Gauss-Newton): minimises
///   sum_i rho(|e_i|^2),  e_i = (pi(R X_i + t) - z_i) / sigma_i,  rho Huber at sqrt(chi2),
/// with the left perturbation T <- [Exp(w) R, Exp(w) t + v], so for P = R X + t
///   de/dv = J_pi / sigma,  de/dw = -J_pi [P]x / sigma,
///   J_pi = [[fx/z, 0, -fx x/z^2], [0, fy/z, -fy y/z^2]];
/// (J^T W J + 1e-9 I) dx = -J^T W e per iteration, stop when |dx| < 1e-10. After each round the
/// correspondences with |e|^2 > chi2 (or behind the camera) are left out of the next round (and
/// may come back); the result's inliers are those of the last round.
RefinementResult refine_pose(const BackendCamera& camera,
                             const std::vector<Correspondence>& correspondences,
                             const Eigen::Isometry3d& T_cam_world,
                             const RegistrationOptions& options);

}  // namespace edx::backend::registration
