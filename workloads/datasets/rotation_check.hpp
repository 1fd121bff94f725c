#pragma once
// Validation of the rotation matrices datasets store as plain numbers (EuRoC T_BS, KITTI poses).
#include <Eigen/Core>
#include <optional>

namespace edx::datasets {

/// The rotation nearest to `matrix` (SVD: U V^T) when `matrix` is one up to rounding, i.e.
/// max |M^T M - I| <= tolerance and det M > 0; std::nullopt otherwise.
std::optional<Eigen::Matrix3d> nearest_rotation(const Eigen::Matrix3d& matrix, double tolerance);

}  // namespace edx::datasets
