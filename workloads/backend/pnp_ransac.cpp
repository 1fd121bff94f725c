#include "workloads/backend/pnp_ransac.hpp"

#include <opencv2/calib3d.hpp>

namespace edx::backend {

std::optional<PnpSolution> pnp_ransac(std::span<const Eigen::Vector3d> object_points,
                                      std::span<const Eigen::Vector2d> image_points,
                                      const PnpIntrinsics& intrinsics,
                                      const PnpRansacSettings& settings) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  object.reserve(object_points.size());
  image.reserve(image_points.size());
  for (const Eigen::Vector3d& X : object_points) object.emplace_back(X.x(), X.y(), X.z());
  for (const Eigen::Vector2d& x : image_points) image.emplace_back(x.x(), x.y());
  const cv::Matx33d K(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
  const int flags =
      settings.method == PnpMethod::kEpnp ? cv::SOLVEPNP_EPNP : cv::SOLVEPNP_ITERATIVE;
  cv::Mat rvec, tvec;
  PnpSolution solution;
  try {
    if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec,
                            /*useExtrinsicGuess=*/false, settings.iterations,
                            static_cast<float>(settings.reprojection_threshold),
                            settings.confidence, solution.inliers, flags)) {
      return std::nullopt;
    }
  } catch (const cv::Exception&) {
    return std::nullopt;  // a failed solve, not a crash
  }
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) solution.T_cam_object.linear()(r, c) = R(r, c);
    solution.T_cam_object.translation()(r) = tvec.at<double>(r);
  }
  return solution;
}

}  // namespace edx::backend
