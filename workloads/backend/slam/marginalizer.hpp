#pragma once
// Marginalization of the oldest keyframe (paper Sec. VI; VINS-Fusion's MarginalizationInfo).
// The variables removed are the oldest keyframe's state x_k (6, or 15 with an IMU) and the m
// landmarks anchored in it (one inverse depth each); the factors touching them (their
// reprojections, the IMU factor to the next keyframe, the previous prior) are linearized into
//   [[A_mm, A_mr], [A_rm, A_rr]] [dx_m; dx_r] = [b_m; b_r],   A_mm = [[A, B], [C, D]]
// with A diagonal (m x m: landmarks only couple through poses) and D the 6x6 pose block. The kept
// variables x_r are the linked kept keyframes and, when it is estimated, the disparity offset
// delta (the removed landmarks' right residuals and the previous prior couple to it), so the new
// prior is on [keyframes | delta] and delta's information accumulates over the run. With an
// IMU, the removed keyframe's velocity and biases (which never couple to landmarks) are
// eliminated first by a 9x9 LDLT (ops ldlt, trsm, trsv, gemm), so that A_mm keeps this
// structure. The Schur complement gives the new prior on the kept states x_r:
//   A_mm^-1 = [[A^-1 + A^-1 B S^-1 C A^-1, -A^-1 B S^-1], [-S^-1 C A^-1, S^-1]],
//             S = D - C A^-1 B                     (inverse exploiting the diagonal + small block)
//   H* = A_rr - A_rm A_mm^-1 A_mr,  b* = b_r - A_rm A_mm^-1 b_m
// stored as a residual r(dx) = r0 + J dx with J^T J = H*, J^T r0 = -b*: LDLT H* = P^T L D L^T P,
// J = D^1/2 L^T P, r0 = -D^-1/2 L^-1 P b* (forward substitution).
// Recorded as the accelerable kernel `marginalization` (m = landmarks removed, n = kept state
// size: kept keyframes times 6 or 15, plus 1 for delta, k = removed keyframe state size) with its
// ops: inverse (kDiagonalBlock | kBlock6x6 | kSymmetric), transpose, gemm, ldlt, trsv.
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

struct MarginalizationReport {
  int landmarks = 0;  ///< m
  int kept_dim = 0;   ///< n
  KeyframeState removed;
  std::vector<Landmark> removed_landmarks;  ///< with world positions in removed_positions
  std::vector<Eigen::Vector3d> removed_positions;
};

/// Removes the oldest keyframe and its landmarks from the window, replacing window.prior.
MarginalizationReport marginalize_oldest(Window& window, const SlamOptions& options,
                                         KernelRecorder& recorder);

/// The structured inverse of A_mm = [[diag(a), B], [B^T, D]] (a > 0), exploiting the diagonal.
Eigen::MatrixXd structured_inverse(const Eigen::VectorXd& a, const Eigen::MatrixXd& B,
                                   const Eigen::MatrixXd& D);

}  // namespace edx::backend::slam
