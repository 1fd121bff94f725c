#pragma once
// Residuals and Jacobians of the window's factors.
//
// Stereo reprojection of landmark (anchor a, bearing m = (x, y, 1), inverse depth rho) into
// keyframe j, whitened by the pixel sigma:
//   P_ba = R_bc m / rho + t_bc,  P_w = R_a P_ba + p_a,  P_bj = R_j^T (P_w - p_j),
//   P_cj = R_bc^T (P_bj - t_bc),  r_left = pi(P_cj) - z_left,  r_right = pi(P_cj - b e_x) + (delta,
//   0) - z_right
// with pi(P) = (fx X/Z + cx, fy Y/Z + cy). In the anchor itself the left residual is zero by
// construction and only the right one (depth) remains. Jacobians (right perturbations):
//   dP_w/dp_a = I, dP_w/dtheta_a = -R_a [P_ba]x, dP_w/drho = -R_a R_bc m / rho^2,
//   dP_bj/dp_j = -R_j^T, dP_bj/dtheta_j = [P_bj]x, dP_cj/dP_w = R_bc^T R_j^T.
//
// IMU factor between consecutive keyframes i, j (world gravity g), 15 residuals:
//   r_p = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2) - alpha(b_i)
//   r_theta = Log(dR(bg_i)^T R_i^T R_j)
//   r_v = R_i^T (v_j - v_i - g dt) - beta(b_i)
//   r_ba = ba_j - ba_i,  r_bg = bg_j - bg_i
// weighted by the preintegration covariance; its 15x30 Jacobian is taken by central
// differences on the state manifold (the residual is cheap and there are window_size - 1).
#include <Eigen/Core>

#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

/// Linearized reprojection factor (residual and Jacobians already whitened).
struct ReprojectionTerm {
  int dim = 0;  ///< 2 (one image) or 4 (left and right)
  Eigen::Matrix<double, 4, 1> r = Eigen::Matrix<double, 4, 1>::Zero();
  Eigen::Matrix<double, 4, 6> J_anchor = Eigen::Matrix<double, 4, 6>::Zero();
  Eigen::Matrix<double, 4, 6> J_target = Eigen::Matrix<double, 4, 6>::Zero();
  Eigen::Matrix<double, 4, 1> J_rho = Eigen::Matrix<double, 4, 1>::Zero();
  /// d r / d delta (disparity offset): 1/sigma on the right image's x row, else 0.
  Eigen::Matrix<double, 4, 1> J_offset = Eigen::Matrix<double, 4, 1>::Zero();
  bool same_frame = false;  ///< observation in the anchor: only J_rho is used
};

/// Computes the term; returns false when the point is behind either camera.
bool linearize_reprojection(const Window& window, const Landmark& landmark,
                            const Observation& observation, double pixel_sigma,
                            ReprojectionTerm& term);

/// Huber weight and cost of a whitened residual norm e: w = 1 (e <= k) or k / e; cost
/// 1/2 e^2 (e <= k) or k (e - k/2).
struct RobustWeight {
  double weight = 1, cost = 0;
};
RobustWeight huber(double e, double k);

/// Unweighted 15-vector IMU residual.
Eigen::Matrix<double, 15, 1> imu_residual(const Preintegration& preintegration,
                                          const KeyframeState& i, const KeyframeState& j,
                                          const Eigen::Vector3d& gravity);

/// Residual and Jacobian [d r / d dx_i, d r / d dx_j] (15x30) by central differences.
void linearize_imu(const Preintegration& preintegration, const KeyframeState& i,
                   const KeyframeState& j, const Eigen::Vector3d& gravity,
                   Eigen::Matrix<double, 15, 1>& r, Eigen::Matrix<double, 15, 30>& J);

/// Information (inverse covariance) of an IMU factor.
Eigen::Matrix<double, 15, 15> imu_information(const Preintegration& preintegration);

}  // namespace edx::backend::slam
