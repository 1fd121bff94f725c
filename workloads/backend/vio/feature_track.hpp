#pragma once
// Feature tracks of the MSCKF and the stereo measurement model in normalized coordinates.
//
// A point p_C in the rectified left camera frame is seen at
//   z = (x_L, y_L, x_R) = (X/Z, Y/Z, (X - b)/Z)
// (the right camera sits at (b, 0, 0) in the left frame with the same orientation, so its
// y equals y_L and is not a separate measurement). Its Jacobian:
//   dz/dp_C = [1/Z 0 -X/Z^2; 0 1/Z -Y/Z^2; 1/Z 0 -(X-b)/Z^2].
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace edx::backend::vio {

/// One observation of a track, in normalized image coordinates ((u - cx)/fx, (v - cy)/fy).
struct Observation {
  std::int64_t t_ns = 0;  ///< the frame (clone) time stamp
  Eigen::Vector2d left = Eigen::Vector2d::Zero();
  bool stereo = false;
  double right_x = 0;  ///< x_R, valid when stereo
  int rows() const { return stereo ? 3 : 2; }
};

struct FeatureTrack {
  std::int64_t id = 0;
  std::vector<Observation> observations;  ///< oldest first
};

/// Predicted measurement of `obs`'s kind for p_C and its Jacobian (rows() x 3).
void project_stereo(const Eigen::Vector3d& p_C, double baseline_m, bool stereo, Eigen::VectorXd& z,
                    Eigen::MatrixXd& dz_dpC);

/// The measured vector of an observation (x_L, y_L[, x_R]).
Eigen::VectorXd measured(const Observation& obs);

}  // namespace edx::backend::vio
