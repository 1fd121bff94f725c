#pragma once
// Levenberg-Marquardt over the sliding window, every matrix operation written out:
//   normal equations   H dx = b,  H = sum J^T W J,  b = -sum J^T W r  (Huber-reweighted)
//   ordering           x = [rho (one per landmark) | keyframe states | delta (disparity
//                      offset, when estimated)], so
//                      H = [[H_ll (diagonal), H_lc], [H_cl, H_cc]]
//   damping            H_ii <- H_ii (1 + lambda)   (Marquardt)
//   Schur complement   S = H_cc - H_cl H_ll^-1 H_lc,  s = b_c - H_cl H_ll^-1 b_l
//                      accumulated landmark by landmark (each couples <= window_size poses)
//   solve              S dx_c = s (LDLT),  dx_l = H_ll^-1 (b_l - H_lc dx_c)
//   step acceptance    gain ratio q = (F(x) - F(x + dx)) / (1/2 dx^T (lambda diag(H) dx + b));
//                      q > 0: accept, lambda *= max(1/3, 1 - (2q - 1)^3); else reject,
//                      lambda *= nu, nu *= 2 (Nielsen).
// Kernels recorded per iteration: linearization (residuals and Jacobians), normal_equations (their
// products, recorded as batched matrix ops), schur_complement, solve, lm_iteration (update,
// cost of the candidate, acceptance).
#include "workloads/backend/kernel_recorder.hpp"
#include "workloads/backend/slam/slam_options.hpp"
#include "workloads/backend/slam/window.hpp"

namespace edx::backend::slam {

struct LmReport {
  int iterations = 0;
  int accepted = 0;
  double initial_cost = 0;
  double final_cost = 0;
  int landmarks = 0;     ///< landmarks in the problem
  int observations = 0;  ///< reprojection terms
};

/// Total cost of the window: robust reprojection + IMU + prior (on keyframes and delta) + the
/// zero-mean prior on delta.
double window_cost(const Window& window, const SlamOptions& options);

/// Optimizes the window in place.
LmReport optimize_window(Window& window, const SlamOptions& options, KernelRecorder& recorder);

/// Marks observations whose reprojection error (px, left or right) exceeds options.outlier_px as
/// outliers and drops landmarks with an invalid depth; returns the observations rejected.
int reject_outliers(Window& window, const SlamOptions& options);

}  // namespace edx::backend::slam
