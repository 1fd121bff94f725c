#include "workloads/backend/vio/triangulation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace edx::backend::vio {
namespace {

std::optional<Eigen::Vector3d> initial_point(const std::vector<Observation>& observations,
                                             const std::vector<CameraPose>& cameras,
                                             double baseline_m) {
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    const double disparity = o.left.x() - o.right_x;
    if (!o.stereo || disparity <= 1e-9) continue;
    const double depth = baseline_m / disparity;
    const Eigen::Vector3d p_C = depth * Eigen::Vector3d(o.left.x(), o.left.y(), 1.0);
    return Eigen::Vector3d(cameras[i].R_WC * p_C + cameras[i].p_WC);
  }
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const Eigen::Vector3d d =
        (cameras[i].R_WC * Eigen::Vector3d(observations[i].left.x(), observations[i].left.y(), 1))
            .normalized();
    const Eigen::Matrix3d N = Eigen::Matrix3d::Identity() - d * d.transpose();
    A += N;
    b += N * cameras[i].p_WC;
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A);
  const Eigen::Vector3d s = svd.singularValues();
  if (s(2) < 1e-6 * s(0)) return std::nullopt;  // rays (nearly) parallel
  return Eigen::Vector3d(A.ldlt().solve(b));
}

}  // namespace

std::optional<TriangulationResult> triangulate(const std::vector<Observation>& observations,
                                               const std::vector<CameraPose>& cameras,
                                               const TriangulationOptions& options) {
  if (observations.empty() || observations.size() != cameras.size()) return std::nullopt;
  const std::optional<Eigen::Vector3d> start =
      initial_point(observations, cameras, options.baseline_m);
  if (!start) return std::nullopt;
  TriangulationResult result;
  Eigen::Vector3d p = *start;
  double lambda = 1e-3;
  const auto cost_of = [&](const Eigen::Vector3d& point, Eigen::Matrix3d* JtJ,
                           Eigen::Vector3d* Jtr) {
    double cost = 0;
    if (JtJ) JtJ->setZero();
    if (Jtr) Jtr->setZero();
    Eigen::VectorXd z;
    Eigen::MatrixXd dz;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      const Eigen::Vector3d p_C = cameras[i].R_WC.transpose() * (point - cameras[i].p_WC);
      if (p_C.z() <= 1e-6) return std::numeric_limits<double>::infinity();
      project_stereo(p_C, options.baseline_m, observations[i].stereo, z, dz);
      const Eigen::VectorXd r = measured(observations[i]) - z;
      cost += r.squaredNorm();
      if (JtJ) {
        const Eigen::MatrixXd J = dz * cameras[i].R_WC.transpose();
        *JtJ += J.transpose() * J;
        *Jtr += J.transpose() * r;
      }
    }
    return cost;
  };
  Eigen::Matrix3d JtJ;
  Eigen::Vector3d Jtr;
  double cost = cost_of(p, &JtJ, &Jtr);
  if (!std::isfinite(cost)) return std::nullopt;
  for (int it = 0; it < options.iterations; ++it) {
    Eigen::Matrix3d damped = JtJ;
    damped.diagonal() *= 1.0 + lambda;
    const Eigen::Vector3d step = damped.ldlt().solve(Jtr);
    const Eigen::Vector3d candidate = p + step;
    const double new_cost = cost_of(candidate, nullptr, nullptr);
    ++result.iterations;
    if (new_cost < cost) {
      p = candidate;
      const bool converged = cost - new_cost < 1e-12 * std::max(1.0, cost) ||
                             step.norm() < 1e-9 * std::max(1.0, p.norm());
      cost = cost_of(p, &JtJ, &Jtr);
      lambda = std::max(lambda * 0.1, 1e-9);
      if (converged) break;
    } else {
      lambda *= 10;
      if (lambda > 1e6) break;
    }
  }
  int rows = 0;
  for (const Observation& o : observations) rows += o.rows();
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const double depth = (cameras[i].R_WC.transpose() * (p - cameras[i].p_WC)).z();
    if (depth < options.min_depth_m || depth > options.max_depth_m) return std::nullopt;
  }
  if (options.max_baseline_ratio > 0) {
    // Conditioning (OpenVINS FeatureInitializer): depth in the first view over the largest
    // distance from its centre to a centre that saw the point; a far point seen over a short
    // baseline has a depth the views do not determine (its linearization is not trustworthy).
    const Eigen::Vector3d c0 = cameras.front().p_WC;
    double baseline = 0;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      baseline = std::max(baseline, (cameras[i].p_WC - c0).norm());
      if (observations[i].stereo) {
        const Eigen::Vector3d right =
            cameras[i].p_WC + cameras[i].R_WC * Eigen::Vector3d(options.baseline_m, 0, 0);
        baseline = std::max(baseline, (right - c0).norm());
      }
    }
    const double depth = (cameras.front().R_WC.transpose() * (p - c0)).z();
    if (!(baseline > 0) || depth > options.max_baseline_ratio * baseline) return std::nullopt;
  }
  result.rms = std::sqrt(cost / std::max(rows, 1));
  if (result.rms > options.max_rms) return std::nullopt;
  result.p_W = p;
  return result;
}

}  // namespace edx::backend::vio
