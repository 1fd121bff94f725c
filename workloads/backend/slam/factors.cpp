#include "workloads/backend/slam/factors.hpp"

#include <cmath>

#include "workloads/backend/so3.hpp"

namespace edx::backend::slam {

bool linearize_reprojection(const Window& window, const Landmark& landmark,
                            const Observation& observation, double pixel_sigma,
                            ReprojectionTerm& term) {
  const BackendCamera& cam = window.camera;
  const Eigen::Matrix3d R_bc = cam.T_body_left.linear();
  const Eigen::Vector3d t_bc = cam.T_body_left.translation();
  const KeyframeState& a = window.keyframe(landmark.anchor_id);
  const double rho = landmark.inverse_depth;
  const Eigen::Vector3d& m = landmark.bearing;
  term = ReprojectionTerm{};
  term.same_frame = observation.keyframe_id == landmark.anchor_id;

  Eigen::Vector3d P_c;
  Eigen::Matrix3d dPc_dPw = Eigen::Matrix3d::Zero();
  Eigen::Vector3d P_ba = R_bc * m / rho + t_bc, P_bj = Eigen::Vector3d::Zero();
  Eigen::Vector3d dPc_drho;
  if (term.same_frame) {
    P_c = m / rho;
    dPc_drho = -m / (rho * rho);
  } else {
    const KeyframeState& j = window.keyframe(observation.keyframe_id);
    const Eigen::Vector3d P_w = a.R * P_ba + a.p;
    P_bj = j.R.transpose() * (P_w - j.p);
    P_c = R_bc.transpose() * (P_bj - t_bc);
    dPc_dPw = R_bc.transpose() * j.R.transpose();
    dPc_drho = dPc_dPw * (a.R * R_bc * (-m / (rho * rho)));
  }
  if (P_c.z() <= 1e-3) return false;

  const double s = 1.0 / pixel_sigma;
  // Rows of one image: d pi / d P at P (left) or P - b e_x (right).
  auto add_image = [&](const Eigen::Vector3d& P, const Eigen::Vector2d& z, double offset_x) {
    const int row = term.dim;
    const double iz = 1.0 / P.z();
    Eigen::Matrix<double, 2, 3> dpi;
    dpi << cam.fx * iz, 0, -cam.fx * P.x() * iz * iz, 0, cam.fy * iz, -cam.fy * P.y() * iz * iz;
    const Eigen::Vector2d uv(cam.fx * P.x() * iz + cam.cx + offset_x, cam.fy * P.y() * iz + cam.cy);
    term.r.segment<2>(row) = s * (uv - z);
    term.J_rho.segment<2>(row) = s * dpi * dPc_drho;
    if (!term.same_frame) {
      const Eigen::Matrix<double, 2, 3> dr_dPw = s * dpi * dPc_dPw;
      term.J_anchor.block<2, 3>(row, 0) = dr_dPw;
      term.J_anchor.block<2, 3>(row, 3) = dr_dPw * (-a.R * skew(P_ba));
      term.J_target.block<2, 3>(row, 0) = -dr_dPw;
      term.J_target.block<2, 3>(row, 3) = s * dpi * R_bc.transpose() * skew(P_bj);
    }
    term.dim += 2;
  };
  if (!term.same_frame) add_image(P_c, observation.left, 0.0);
  if (observation.right) {
    const Eigen::Vector3d P_r = P_c - Eigen::Vector3d(cam.baseline_m, 0, 0);
    if (P_r.z() > 1e-3) {
      term.J_offset(term.dim) = s;
      add_image(P_r, *observation.right, window.disparity_offset_px);
    }
  }
  return term.dim > 0;
}

RobustWeight huber(double e, double k) {
  if (e <= k) return {1.0, 0.5 * e * e};
  return {k / e, k * (e - 0.5 * k)};
}

Eigen::Matrix<double, 15, 1> imu_residual(const Preintegration& pre, const KeyframeState& i,
                                          const KeyframeState& j, const Eigen::Vector3d& g) {
  const double dt = pre.dt();
  Eigen::Matrix<double, 15, 1> r;
  r.segment<3>(0) = i.R.transpose() * (j.p - i.p - i.v * dt - 0.5 * g * dt * dt) -
                    pre.corrected_alpha(i.ba, i.bg);
  r.segment<3>(3) = so3_log(pre.corrected_delta_R(i.bg).transpose() * i.R.transpose() * j.R);
  r.segment<3>(6) = i.R.transpose() * (j.v - i.v - g * dt) - pre.corrected_beta(i.ba, i.bg);
  r.segment<3>(9) = j.ba - i.ba;
  r.segment<3>(12) = j.bg - i.bg;
  return r;
}

void linearize_imu(const Preintegration& pre, const KeyframeState& i, const KeyframeState& j,
                   const Eigen::Vector3d& gravity, Eigen::Matrix<double, 15, 1>& r,
                   Eigen::Matrix<double, 15, 30>& J) {
  r = imu_residual(pre, i, j, gravity);
  const KeyframeState nav_i = i.navigation_state(), nav_j = j.navigation_state();
  constexpr double h = 1e-6;
  for (int c = 0; c < 30; ++c) {
    KeyframeState xi_plus = nav_i, xi_minus = nav_i, xj_plus = nav_j, xj_minus = nav_j;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(15);
    d(c % 15) = h;
    if (c < 15) {
      xi_plus.apply_increment(d, 15);
      xi_minus.apply_increment(-d, 15);
    } else {
      xj_plus.apply_increment(d, 15);
      xj_minus.apply_increment(-d, 15);
    }
    J.col(c) = (imu_residual(pre, xi_plus, xj_plus, gravity) -
                imu_residual(pre, xi_minus, xj_minus, gravity)) /
               (2 * h);
  }
}

Eigen::Matrix<double, 15, 15> imu_information(const Preintegration& pre) {
  Eigen::Matrix<double, 15, 15> cov = pre.covariance();
  cov.diagonal().array() += 1e-12;  // keeps the bias blocks invertible on very short intervals
  Eigen::Matrix<double, 15, 15> info = cov.ldlt().solve(Eigen::Matrix<double, 15, 15>::Identity());
  return 0.5 * (info + info.transpose());
}

}  // namespace edx::backend::slam
