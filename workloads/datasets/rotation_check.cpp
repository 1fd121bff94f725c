#include "workloads/datasets/rotation_check.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace edx::datasets {

std::optional<Eigen::Matrix3d> nearest_rotation(const Eigen::Matrix3d& matrix, double tolerance) {
  const double orthonormality_error =
      (matrix.transpose() * matrix - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(orthonormality_error <= tolerance) || !(matrix.determinant() > 0)) return std::nullopt;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(matrix, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace edx::datasets
