#include "workloads/backend/registration/pose_solver.hpp"

#include <cmath>
#include <optional>

#include "workloads/backend/pnp_ransac.hpp"
#include "workloads/backend/so3.hpp"

namespace edx::backend::registration {

Eigen::Matrix<double, 3, 4> camera_matrix(const BackendCamera& camera,
                                          const Eigen::Isometry3d& T_cam_world) {
  Eigen::Matrix3d K;
  K << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1;
  return K * T_cam_world.matrix().topRows<3>();
}

Eigen::Matrix3Xd project(const Eigen::Matrix<double, 3, 4>& C, const Eigen::Matrix4Xd& X,
                         trace::Precision precision) {
  if (precision == trace::Precision::kFp32) {
    return (C.cast<float>() * X.cast<float>()).cast<double>();
  }
  return C * X;
}

PnpResult solve_pnp_ransac(const BackendCamera& camera,
                           const std::vector<Correspondence>& correspondences,
                           const RegistrationOptions& options) {
  PnpResult result;
  if (correspondences.size() < 4) return result;
  std::vector<Eigen::Vector3d> world;
  std::vector<Eigen::Vector2d> pixels;
  world.reserve(correspondences.size());
  pixels.reserve(correspondences.size());
  for (const Correspondence& c : correspondences) {
    world.push_back(c.world);
    pixels.push_back(c.pixel);
  }
  const std::optional<PnpSolution> solution =
      pnp_ransac(world, pixels, {camera.fx, camera.fy, camera.cx, camera.cy},
                 {.iterations = options.pnp_iterations,
                  .reprojection_threshold = options.pnp_reprojection_px,
                  .confidence = options.pnp_confidence,
                  .method = PnpMethod::kEpnp});
  if (!solution || static_cast<int>(solution->inliers.size()) < options.pnp_min_inliers) {
    return result;
  }
  if (!solution->T_cam_object.matrix().allFinite()) return result;
  result.T_cam_world = solution->T_cam_object;
  result.inliers.assign(solution->inliers.begin(), solution->inliers.end());
  result.ok = true;
  return result;
}

RefinementResult refine_pose(const BackendCamera& camera,
                             const std::vector<Correspondence>& correspondences,
                             const Eigen::Isometry3d& T_cam_world,
                             const RegistrationOptions& options) {
  RefinementResult result;
  result.T_cam_world = T_cam_world;
  const std::size_t n = correspondences.size();
  result.inlier.assign(n, true);
  if (n == 0) return result;
  const double huber = std::sqrt(options.chi2_threshold);
  Eigen::Matrix3d R = T_cam_world.linear();
  Eigen::Vector3d t = T_cam_world.translation();

  // Whitened residual of one correspondence; false when the point is not in front.
  const auto residual = [&](const Correspondence& c, Eigen::Vector3d& P, Eigen::Vector2d& e) {
    P = R * c.world + t;
    if (P.z() <= 1e-6) return false;
    const Eigen::Vector2d uv(camera.fx * P.x() / P.z() + camera.cx,
                             camera.fy * P.y() / P.z() + camera.cy);
    e = (uv - c.pixel) / c.sigma_px;
    return true;
  };

  for (int round = 0; round < options.refinement_rounds; ++round) {
    for (int it = 0; it < options.refinement_iterations; ++it) {
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
      int used = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (!result.inlier[i]) continue;
        const Correspondence& c = correspondences[i];
        Eigen::Vector3d P = Eigen::Vector3d::Zero();
        Eigen::Vector2d e = Eigen::Vector2d::Zero();
        if (!residual(c, P, e)) continue;
        const double z_inv = 1.0 / P.z();
        Eigen::Matrix<double, 2, 3> Jpi;
        Jpi << camera.fx * z_inv, 0, -camera.fx * P.x() * z_inv * z_inv, 0, camera.fy * z_inv,
            -camera.fy * P.y() * z_inv * z_inv;
        Jpi /= c.sigma_px;
        Eigen::Matrix<double, 2, 6> J;
        J.leftCols<3>() = -Jpi * skew(P);  // d/dw
        J.rightCols<3>() = Jpi;            // d/dv
        const double norm = e.norm();
        const double w = norm <= huber ? 1.0 : huber / norm;  // Huber IRLS weight
        H.noalias() += w * J.transpose() * J;
        g.noalias() += w * J.transpose() * e;
        ++used;
      }
      if (used < 3) break;
      const Eigen::Matrix<double, 6, 1> dx =
          (H + 1e-9 * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(-g);
      if (!dx.allFinite()) break;
      const Eigen::Matrix3d dR = so3_exp(dx.head<3>());
      R = dR * R;
      t = dR * t + dx.tail<3>();
      ++result.iterations;
      if (dx.norm() < 1e-10) break;
    }
    // Classify every correspondence against the current pose (outliers may come back).
    for (std::size_t i = 0; i < n; ++i) {
      Eigen::Vector3d P = Eigen::Vector3d::Zero();
      Eigen::Vector2d e = Eigen::Vector2d::Zero();
      result.inlier[i] =
          residual(correspondences[i], P, e) && e.squaredNorm() <= options.chi2_threshold;
    }
  }
  double sum_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!result.inlier[i]) continue;
    Eigen::Vector3d P = Eigen::Vector3d::Zero();
    Eigen::Vector2d e = Eigen::Vector2d::Zero();
    residual(correspondences[i], P, e);
    sum_sq += (e * correspondences[i].sigma_px).squaredNorm();
    ++result.inliers;
  }
  result.rms_px = result.inliers > 0 ? std::sqrt(sum_sq / result.inliers) : 0.0;
  // Re-orthonormalise the accumulated rotation.
  result.T_cam_world.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  result.T_cam_world.translation() = t;
  return result;
}

}  // namespace edx::backend::registration
