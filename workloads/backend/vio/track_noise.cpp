#include "workloads/backend/vio/track_noise.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace edx::backend::vio {

Eigen::MatrixXd track_covariance(const std::vector<Observation>& observations,
                                 const RandomWalkTrackNoise& noise, double focal_px,
                                 std::span<const double> depths_m) {
  if (!depths_m.empty() && depths_m.size() != observations.size()) {
    throw std::invalid_argument("track_covariance: expected one depth per observation");
  }
  Eigen::Index rows = 0;
  for (const Observation& o : observations) rows += o.rows();
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(rows, rows);
  // Per observation: C_i in px^2 and its rows (x_L, y_L, x_R or -1).
  std::vector<double> C(observations.size());
  std::vector<std::array<Eigen::Index, 3>> at(observations.size());
  double c = noise.detection_sigma_px * noise.detection_sigma_px;
  Eigen::Index row = 0;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    if (i > 0) {
      const double flow = focal_px * (observations[i].left - observations[i - 1].left).norm();
      const double b_flow = noise.step_flow_fraction * flow;
      c += noise.step_sigma_px * noise.step_sigma_px + b_flow * b_flow;
      if (!depths_m.empty()) {
        const double c_scale = noise.step_scale_px * std::abs(depths_m[i - 1] / depths_m[i] - 1.0);
        c += c_scale * c_scale;
      }
    }
    C[i] = c;
    at[i] = {row, row + 1, observations[i].stereo ? row + 2 : -1};
    row += observations[i].rows();
  }
  for (std::size_t i = 0; i < observations.size(); ++i) {
    for (std::size_t j = 0; j < observations.size(); ++j) {
      const double shared = C[std::min(i, j)];
      R(at[i][1], at[j][1]) = shared;
      for (const Eigen::Index a : {at[i][0], at[i][2]})
        for (const Eigen::Index b : {at[j][0], at[j][2]})
          if (a >= 0 && b >= 0) R(a, b) = shared;
    }
    if (at[i][2] >= 0) R(at[i][2], at[i][2]) += noise.disparity_sigma_px * noise.disparity_sigma_px;
  }
  return R / (focal_px * focal_px);
}

}  // namespace edx::backend::vio
