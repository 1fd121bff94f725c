#include "workloads/backend/slam/tracker.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <optional>

#include "workloads/backend/pnp_ransac.hpp"
#include "workloads/backend/slam/factors.hpp"
#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {
namespace {

struct Match {
  std::int64_t track_id = 0;
  Eigen::Vector3d X;
  Eigen::Vector2d left;
  std::optional<Eigen::Vector2d> right;
  bool inlier = true;
};

/// One image's residual (px) and its 2x6 Jacobian for camera point P_c (offset by -b e_x for the
/// right image).
void image_term(const BackendCamera& cam, const Eigen::Vector3d& P_c, const Eigen::Vector2d& z,
                double offset_x, const Eigen::Matrix<double, 3, 6>& dPc_dx, Eigen::Vector2d& r,
                Eigen::Matrix<double, 2, 6>& J) {
  const double iz = 1.0 / P_c.z();
  Eigen::Matrix<double, 2, 3> dpi;
  dpi << cam.fx * iz, 0, -cam.fx * P_c.x() * iz * iz, 0, cam.fy * iz, -cam.fy * P_c.y() * iz * iz;
  r = Eigen::Vector2d(cam.fx * P_c.x() * iz + cam.cx + offset_x, cam.fy * P_c.y() * iz + cam.cy) -
      z;
  J = dpi * dPc_dx;
}

}  // namespace

TrackingResult track_frame(const Window& window, const std::vector<frontend::Feature>& features,
                           const Eigen::Isometry3d& initial_T_world_body,
                           const SlamOptions& options) {
  const BackendCamera& cam = window.camera;
  std::vector<Match> matches;
  for (const frontend::Feature& f : features) {
    const auto it = window.landmarks.find(f.id);
    if (it == window.landmarks.end() || !(it->second.inverse_depth > 0)) continue;
    Match m;
    m.track_id = f.id;
    m.X = window.landmark_world(it->second);
    m.left = {f.left.x, f.left.y};
    const double depth = 1.0 / it->second.inverse_depth;
    if (f.stereo && (options.stereo_max_depth_baselines <= 0 ||
                     depth < options.stereo_max_depth_baselines * cam.baseline_m)) {
      m.right = Eigen::Vector2d(f.right.x, f.right.y);
    }
    matches.push_back(m);
  }
  TrackingResult result;
  result.matches = static_cast<int>(matches.size());
  result.T_world_body = initial_T_world_body;
  if (result.matches < options.tracking_min_matches) return result;

  const Eigen::Matrix3d R_bc = cam.T_body_left.linear();
  const Eigen::Vector3d t_bc = cam.T_body_left.translation();
  Eigen::Matrix3d R = initial_T_world_body.linear();
  Eigen::Vector3d p = initial_T_world_body.translation();
  const double k = options.huber_threshold * options.pixel_sigma;
  auto refine = [&](int iterations) {
    for (int it = 0; it < iterations; ++it) {
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      for (const Match& m : matches) {
        if (!m.inlier) continue;
        const Eigen::Vector3d P_b = R.transpose() * (m.X - p);
        const Eigen::Vector3d P_c = R_bc.transpose() * (P_b - t_bc);
        if (P_c.z() < 1e-3) continue;
        Eigen::Matrix<double, 3, 6> dPc_dx;
        dPc_dx.leftCols<3>() = -R_bc.transpose() * R.transpose();
        dPc_dx.rightCols<3>() = R_bc.transpose() * skew(P_b);
        Eigen::Vector2d r;
        Eigen::Matrix<double, 2, 6> J;
        image_term(cam, P_c, m.left, 0.0, dPc_dx, r, J);
        double w = huber(r.norm(), k).weight;
        H += w * J.transpose() * J;
        b -= w * J.transpose() * r;
        if (m.right) {
          const Eigen::Vector3d P_r = P_c - Eigen::Vector3d(cam.baseline_m, 0, 0);
          image_term(cam, P_r, *m.right, window.disparity_offset_px, dPc_dx, r, J);
          w = huber(r.norm(), k).weight;
          H += w * J.transpose() * J;
          b -= w * J.transpose() * r;
        }
      }
      H.diagonal().array() += 1e-6;
      const Eigen::Matrix<double, 6, 1> dx = H.ldlt().solve(b);
      if (!dx.allFinite()) return;
      p += dx.head<3>();
      R = R * so3_exp(dx.tail<3>());
      if (dx.norm() < 1e-8) return;
    }
  };
  auto classify = [&]() {
    int inliers = 0;
    double sum_sq = 0;
    for (Match& m : matches) {
      const Eigen::Vector3d P_c = R_bc.transpose() * (R.transpose() * (m.X - p) - t_bc);
      if (P_c.z() < 1e-3) {
        m.inlier = false;
        continue;
      }
      const Eigen::Vector2d uv(cam.fx * P_c.x() / P_c.z() + cam.cx,
                               cam.fy * P_c.y() / P_c.z() + cam.cy);
      const double e = (uv - m.left).norm();
      m.inlier = e <= options.outlier_px;
      if (m.inlier) {
        ++inliers;
        sum_sq += e * e;
      }
    }
    result.inliers = inliers;
    result.rms_px = inliers > 0 ? std::sqrt(sum_sq / inliers) : 0;
  };
  // Starting pose: the prediction, or RANSAC PnP when that explains more matches.
  classify();
  const int predicted_inliers = result.inliers;
  {
    std::vector<Eigen::Vector3d> world;
    std::vector<Eigen::Vector2d> left;
    for (const Match& m : matches) {
      world.push_back(m.X);
      left.push_back(m.left);
    }
    const std::optional<PnpSolution> solution =
        pnp_ransac(world, left, {cam.fx, cam.fy, cam.cx, cam.cy},
                   {.iterations = 100,
                    .reprojection_threshold = options.outlier_px,
                    .confidence = 0.99,
                    .method = PnpMethod::kEpnp});
    if (solution && static_cast<int>(solution->inliers.size()) > predicted_inliers) {
      // T_world_body = T_world_cam T_cam_body = (T_cam_world)^-1 T_body_left^-1.
      const Eigen::Isometry3d T_world_body =
          solution->T_cam_object.inverse() * cam.T_body_left.inverse();
      R = T_world_body.linear();
      p = T_world_body.translation();
      result.used_ransac = true;
      classify();
    }
  }
  refine(options.tracking_iterations);
  classify();
  refine(options.tracking_iterations / 2 + 1);
  classify();
  result.ok = result.inliers >= options.tracking_min_matches;
  for (const Match& m : matches) {
    if (m.inlier) result.inlier_tracks.push_back(m.track_id);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = p;
  if (result.ok) result.T_world_body = T;
  return result;
}

}  // namespace edx::backend::slam
