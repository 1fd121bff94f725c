#include "workloads/eval/alignment.hpp"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace edx::eval {

AlignmentMethod parse_alignment_method(std::string_view name) {
  if (name == "none") return AlignmentMethod::kNone;
  if (name == "se3") return AlignmentMethod::kSe3;
  if (name == "sim3") return AlignmentMethod::kSim3;
  if (name == "posyaw") return AlignmentMethod::kPosYaw;
  throw std::runtime_error(
      fmt::format("unknown alignment '{}' (expected none, se3, sim3 or posyaw)", name));
}

std::string_view alignment_method_name(AlignmentMethod method) {
  switch (method) {
    case AlignmentMethod::kNone:
      return "none";
    case AlignmentMethod::kSe3:
      return "se3";
    case AlignmentMethod::kSim3:
      return "sim3";
    case AlignmentMethod::kPosYaw:
      return "posyaw";
  }
  return "unknown";
}

std::size_t min_pairs_for(AlignmentMethod method) {
  switch (method) {
    case AlignmentMethod::kNone:
      return 1;
    case AlignmentMethod::kPosYaw:
      return 2;
    case AlignmentMethod::kSe3:
    case AlignmentMethod::kSim3:
      return 3;
  }
  return 3;
}

SimilarityTransform align_positions(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt,
                                    AlignmentMethod method) {
  if (est.cols() != gt.cols()) {
    throw std::invalid_argument("align_positions: est and gt hold different numbers of positions");
  }
  const auto count = static_cast<std::size_t>(est.cols());
  if (count < min_pairs_for(method)) {
    throw std::runtime_error(
        fmt::format("too few pose pairs for {} alignment: {} (need at least {})",
                    alignment_method_name(method), count, min_pairs_for(method)));
  }
  SimilarityTransform transform;
  switch (method) {
    case AlignmentMethod::kNone:
      break;
    case AlignmentMethod::kSe3:
    case AlignmentMethod::kSim3: {
      const bool with_scale = method == AlignmentMethod::kSim3;
      if (with_scale) {
        // Umeyama's scale divides by the spread of the estimated positions.
        const Eigen::Vector3d mean = est.rowwise().mean();
        if ((est.colwise() - mean).squaredNorm() <= 0.0) {
          throw std::runtime_error(
              "cannot align sim3: the estimated positions do not move (zero spread)");
        }
      }
      // Eigen::umeyama returns [cR | t] minimising sum |gt_i - (c R est_i + t)|^2.
      const Eigen::Matrix4d cRt = Eigen::umeyama(est, gt, with_scale);
      const Eigen::Matrix3d scaled_rotation = cRt.topLeftCorner<3, 3>();
      transform.scale = with_scale ? scaled_rotation.col(0).norm() : 1.0;
      if (!(transform.scale > 0.0)) {
        throw std::runtime_error(
            "cannot align sim3: the ground-truth positions do not move (zero spread)");
      }
      transform.rotation = scaled_rotation / transform.scale;
      transform.translation = cRt.topRightCorner<3, 1>();
      break;
    }
    case AlignmentMethod::kPosYaw: {
      const Eigen::Vector3d est_mean = est.rowwise().mean();
      const Eigen::Vector3d gt_mean = gt.rowwise().mean();
      const Eigen::Matrix3d c =
          (est.colwise() - est_mean) * (gt.colwise() - gt_mean).transpose();  // sum e_i g_i^T
      // sum g^T Rz e = cos(th) (C00 + C11) + sin(th) (C01 - C10) + C22, maximal at:
      const double yaw = std::atan2(c(0, 1) - c(1, 0), c(0, 0) + c(1, 1));
      transform.rotation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      transform.translation = gt_mean - transform.rotation * est_mean;
      break;
    }
  }
  return transform;
}

}  // namespace edx::eval
