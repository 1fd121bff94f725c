#pragma once
// Multi-view triangulation of a feature track from the clone camera poses (Gauss-Newton).
//
// Initial point: the stereo depth of the first stereo observation, Z = b / (x_L - x_R),
// p_C = Z (x_L, y_L, 1); without stereo, the least-squares intersection of the viewing rays,
// sum_i (I - d_i d_i^T) p = sum_i (I - d_i d_i^T) c_i. Then Gauss-Newton (Levenberg damping) on
// the world point minimising sum_i |z_i - h(R_CiW (p - c_i))|^2 over every left and right
// observation (feature_track.hpp's model).
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "workloads/backend/vio/feature_track.hpp"

namespace edx::backend::vio {

/// A camera pose: p_W = R_WC p_C + p_WC.
struct CameraPose {
  Eigen::Matrix3d R_WC = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WC = Eigen::Vector3d::Zero();
};

struct TriangulationOptions {
  double baseline_m = 0;
  double min_depth_m = 0.2, max_depth_m = 150.0;
  /// Largest depth / baseline accepted (OpenVINS max_baseline): the depth in the first view over
  /// the longest distance between the camera centres that saw the point (the clones' left
  /// cameras and, for stereo observations, their right cameras). 0: no check.
  double max_baseline_ratio = 0;
  double max_rms = 0;  ///< largest RMS residual (normalized units) accepted
  int iterations = 10;
};

struct TriangulationResult {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  double rms = 0;      ///< RMS residual after the last iteration, normalized units
  int iterations = 0;  ///< Gauss-Newton iterations run
};

/// Triangulates one track; cameras[i] is the pose of observations[i]. Returns nullopt when the
/// geometry is degenerate, the point falls outside the depth range in any view, is too far for
/// the baseline that saw it (max_baseline_ratio), or the residual stays above max_rms.
std::optional<TriangulationResult> triangulate(const std::vector<Observation>& observations,
                                               const std::vector<CameraPose>& cameras,
                                               const TriangulationOptions& options);

}  // namespace edx::backend::vio
