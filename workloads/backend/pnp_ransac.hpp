#pragma once
// RANSAC PnP, the one call to OpenCV's solver behind every backend's absolute pose: the
// registration backend's localization against the map, SLAM's tracking start and the VIO
// initializer's frame-to-frame chain. cv::solvePnPRansac draws minimal sets with OpenCV's fixed
// RNG seed (deterministic), solves each with the chosen method, counts the pairs whose
// reprojection error |pi(K (R X_i + t)) - x_i| is within the threshold and refines on the largest
// consensus set. No initial guess (useExtrinsicGuess = false), no distortion (rectified images).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <span>
#include <vector>

namespace edx::backend {

/// Pinhole intrinsics of the image points: pixels (fx, fy, cx, cy), or normalized image
/// coordinates with the defaults (K = I).
struct PnpIntrinsics {
  double fx = 1, fy = 1, cx = 0, cy = 0;
};

/// The minimal solver of each RANSAC hypothesis (cv::SOLVEPNP_*).
enum class PnpMethod { kEpnp, kIterative };

/// RANSAC settings, handed to cv::solvePnPRansac as they are (each caller keeps its own).
struct PnpRansacSettings {
  int iterations = 100;
  double reprojection_threshold = 8;  ///< in the image points' unit; OpenCV takes it as float
  double confidence = 0.99;
  PnpMethod method = PnpMethod::kIterative;
};

struct PnpSolution {
  Eigen::Isometry3d T_cam_object = Eigen::Isometry3d::Identity();  ///< x ~ K (R X + t)
  std::vector<int> inliers;  ///< indices into the point pairs, increasing
};

/// The pose of the camera that sees object_points[i] at image_points[i] (equal sizes).
/// std::nullopt when the solve fails: OpenCV finds no pose, or throws cv::Exception (too few
/// points, degenerate configurations such as collinear points). The pose is as OpenCV returns
/// it (Rodrigues of its rotation vector), not checked for finiteness.
std::optional<PnpSolution> pnp_ransac(std::span<const Eigen::Vector3d> object_points,
                                      std::span<const Eigen::Vector2d> image_points,
                                      const PnpIntrinsics& intrinsics,
                                      const PnpRansacSettings& settings);

}  // namespace edx::backend
