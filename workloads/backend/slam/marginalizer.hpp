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
//   A_mm^-1 by a general dense symmetric (pseudo-)inverse, as a CPU implementation does
//           (VINS-Mono: eigen-decomposition, O((m+6)^3)); the structure is only recorded in the
//           op's flags, for the accelerator's specialized inverse (paper Sec. VI-A)
//   H* = A_rr - A_rm A_mm^-1 A_mr,  b* = b_r - A_rm A_mm^-1 b_m
// stored as a residual r(dx) = r0 + J dx with J^T J = H*, J^T r0 = -b*: LDLT H* = P^T L D L^T P,
// J = D^1/2 L^T P, r0 = -D^-1/2 L^-1 P b* (forward substitution).
// Recorded as the accelerable kernel `marginalization` (m = landmarks removed, n = kept state
// size: kept keyframes times 6 or 15, plus 1 for delta, k = removed keyframe state size) with its
// ops: inverse (m+6, flags kDiagonalBlock | kBlock6x6 | kSymmetric: the structure, which the
// host does not use), transpose, gemm, ldlt, trsv.
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

/// The normal equations H dx = b of every factor touching the removed variables, over
/// [rho of the m removed landmarks | oldest keyframe (d) | kept keyframes (d each) | delta].
struct MarginalizationSystem {
  int m = 0;                                 ///< landmarks anchored in the oldest keyframe
  int d = 0;                                 ///< keyframe state size (6, or 15 with an IMU)
  int r = 0;                                 ///< kept size: kept keyframes x d, plus 1 for delta
  bool keeps_offset = false;                 ///< delta is the last kept variable
  std::vector<std::int64_t> removed_tracks;  ///< track ids of the m landmarks, in H's order
  std::vector<int> kept_slots;               ///< window slot of each kept keyframe block
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
};

/// Linearizes the factors touching the oldest keyframe and its landmarks (the window is not
/// changed). The landmark block H[0:m, 0:m] is diagonal: landmarks couple only through poses.
MarginalizationSystem linearize_marginalization(const Window& window, const SlamOptions& options);

/// Removes the oldest keyframe and its landmarks from the window, replacing window.prior.
MarginalizationReport marginalize_oldest(Window& window, const SlamOptions& options,
                                         KernelRecorder& recorder);

/// Eigenvalues at or below this are dropped by the pseudo-inverse (VINS-Mono's `eps`).
inline constexpr double kPseudoInverseEpsilon = 1e-8;

/// The inverse of a symmetric matrix by its eigen-decomposition, A^+ = V diag(1/λ) V^T over the
/// eigenvalues λ > kPseudoInverseEpsilon (the others dropped): a general dense inverse.
Eigen::MatrixXd symmetric_pseudo_inverse(const Eigen::MatrixXd& A);

}  // namespace edx::backend::slam
