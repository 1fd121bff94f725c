#pragma once
// Noise model of one feature track's stacked measurement rows (docs/VIO.md "Track noise").
//
// Random walk: the frontend tracks a feature frame to frame (LK), so the position error of its
// i-th observation is the sum of the steps' errors,
//   e_i = e_0 + s_1 + ... + s_i,  e_0 ~ N(0, sd^2) (detection),
//   s_k ~ N(0, a^2 + (b f_k)^2 + (c g_k)^2) per axis, f_k = |x_k - x_(k-1)| the step's image
//   motion (px), g_k = |Z_(k-1) / Z_k - 1| the patch's scale change (Z: the point's depth in
//   each observation's camera; LK's translation-only patch model misses it),
// independently in x and y. The right image's x is the left x minus a disparity measured afresh
// each frame (DR), so it carries the same e_i plus N(0, sigma_d^2). With C_i = sd^2 + sum_(k<=i)
// (a^2 + (b f_k)^2):
// (c g_k)^2 enters only when the depths are given.
//   cov(x_i, x_j) = cov(y_i, y_j) = C_min(i,j),  cov(x_i, y_j) = 0,
//   the right rows: the same plus sigma_d^2 on their own diagonal entry.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "workloads/backend/vio/feature_track.hpp"

namespace edx::backend::vio {

/// Defaults: measured against the rendered depth (docs/VIO.md, "Random-walk track noise"): sd
/// and sigma_d on development seed 1 (EuRoC rig), a and c from the step errors binned by scale
/// change on the EuRoC and car rigs; b = 0, the scale change explains what motion did.
struct RandomWalkTrackNoise {
  double detection_sigma_px = 0.3;   ///< sd: the first observation's error
  double step_sigma_px = 0.06;       ///< a: a step's error at no scale change or motion
  double step_flow_fraction = 0;     ///< b: a step's error per pixel of image motion
  double step_scale_px = 3.7;        ///< c: a step's error per unit of scale change, px
  double disparity_sigma_px = 0.15;  ///< sigma_d: DR's disparity error
};

/// Covariance of the rows (x_L, y_L[, x_R] per observation, in order) of `observations`, in
/// normalized image units (pixels / focal_px). `depths_m`: the point's depth in each
/// observation's camera (same order), for the scale-change term; empty: no such term.
Eigen::MatrixXd track_covariance(const std::vector<Observation>& observations,
                                 const RandomWalkTrackNoise& noise, double focal_px,
                                 std::span<const double> depths_m = {});

}  // namespace edx::backend::vio
