#include "workloads/backend/vio/gps_fusion.hpp"

#include <fmt/format.h>

#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/backend/vio/ekf_update.hpp"
#include "workloads/eval/alignment.hpp"

namespace edx::backend::vio {

GpsFusion::GpsFusion(const VioOptions& options) : options_(options) {}

void GpsFusion::align(VioState& state) {
  const Eigen::Index count = static_cast<Eigen::Index>(fix_positions_.size());
  Eigen::Matrix3Xd est(3, count), gps(3, count);
  for (Eigen::Index i = 0; i < count; ++i) {
    est.col(i) = filter_positions_[static_cast<std::size_t>(i)];
    gps.col(i) = fix_positions_[static_cast<std::size_t>(i)];
  }
  const eval::SimilarityTransform T =
      eval::align_positions(est, gps, eval::AlignmentMethod::kPosYaw);
  state.yaw_GV = std::atan2(T.rotation(1, 0), T.rotation(0, 0));
  state.t_GV = T.translation;
  double sigma2 = 0, spread = 0;
  const Eigen::Vector3d mean = gps.rowwise().mean();
  for (Eigen::Index i = 0; i < count; ++i) {
    const double s = fix_sigmas_[static_cast<std::size_t>(i)];
    sigma2 += s * s / static_cast<double>(count);
    spread += (gps.col(i) - mean).head<2>().squaredNorm();
  }
  // t is the translation at the filter's origin: its variance grows with the lever |mean_W|.
  const double var_yaw = sigma2 / spread;
  const Eigen::Vector3d mean_w = est.rowwise().mean();
  const Eigen::Vector3d lever = skew(Eigen::Vector3d::UnitZ()) * T.rotation * mean_w;
  state.P.row(kGpsYaw).setZero();
  state.P.col(kGpsYaw).setZero();
  state.P.middleRows<3>(kGpsPos).setZero();
  state.P.middleCols<3>(kGpsPos).setZero();
  state.P(kGpsYaw, kGpsYaw) = var_yaw;
  // t = mean_G - Rz mean_W: var(t) = sigma^2/n I + lever var_yaw lever^T, cov(t, yaw) = -lever.
  state.P.block<3, 3>(kGpsPos, kGpsPos) =
      sigma2 / static_cast<double>(count) * Eigen::Matrix3d::Identity() +
      var_yaw * lever * lever.transpose();
  state.P.block<3, 1>(kGpsPos, kGpsYaw) = -var_yaw * lever;
  state.P.block<1, 3>(kGpsYaw, kGpsPos) = -var_yaw * lever.transpose();
  aligned_ = true;
}

GpsReport GpsFusion::process(VioState& state, std::span<const datasets::GpsFix> fixes,
                             KernelRecorder& recorder) {
  GpsReport report;
  report.fixes = static_cast<int>(fixes.size());
  if (!options_.use_gps || fixes.empty()) return report;
  auto kernel = recorder.kernel("gps_fusion");
  kernel.record().m = report.fixes;
  kernel.record().n = state.dim();
  const Eigen::Vector3d& lever = options_.gps_lever_arm_m;
  // Antenna position in the filter's world frame at the fix time.
  const auto antenna = [&](const datasets::GpsFix& fix) {
    const double dt = static_cast<double>(state.t_ns - fix.t_ns) * 1e-9;
    return Eigen::Vector3d(state.p_WI + state.R_WI * lever - state.v_WI * dt);
  };
  if (!aligned_) {
    for (const auto& fix : fixes) {
      filter_positions_.push_back(antenna(fix));
      fix_positions_.push_back(fix.position_m);
      fix_sigmas_.push_back(std::max(fix.sigma_m, options_.gps_sigma_floor_m));
    }
    Eigen::Vector2d lo = fix_positions_.front().head<2>(), hi = lo;
    for (const auto& p : fix_positions_) {
      lo = lo.cwiseMin(p.head<2>());
      hi = hi.cwiseMax(p.head<2>());
    }
    if (static_cast<int>(fix_positions_.size()) >= options_.gps_align_min_fixes &&
        (hi - lo).norm() >= options_.gps_align_min_extent_m) {
      align(state);
      report.aligned_now = true;
    }
    kernel.record().detail_json = fmt::format(R"({{"aligned":{}}})", aligned_);
    return report;
  }
  const double gate = chi2_quantile(options_.gps_chi2_confidence, 3);
  for (const auto& fix : fixes) {
    const int n = state.dim();
    const double sigma = std::max(fix.sigma_m, options_.gps_sigma_floor_m);
    const double dt = static_cast<double>(state.t_ns - fix.t_ns) * 1e-9;
    const Eigen::Matrix3d Rz =
        Eigen::AngleAxisd(state.yaw_GV, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d a = antenna(fix);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, n);
    H.block<3, 3>(0, kTheta) = -Rz * skew(state.R_WI * lever);
    H.block<3, 3>(0, kPos) = Rz;
    H.block<3, 3>(0, kVel) = -dt * Rz;
    H.block<3, 1>(0, kGpsYaw) = skew(Eigen::Vector3d::UnitZ()) * Rz * a;
    H.block<3, 3>(0, kGpsPos).setIdentity();
    const Eigen::Vector3d r = fix.position_m - (Rz * a + state.t_GV);
    const Eigen::Vector3d noise = Eigen::Vector3d::Constant(sigma * sigma);
    Eigen::Matrix3d S = H * state.P * H.transpose();
    S.diagonal() += noise;
    const double gamma = r.dot(S.ldlt().solve(r));
    if (gamma > gate && consecutive_rejections_ < 20) {
      ++report.rejected;
      ++consecutive_rejections_;
      continue;
    }
    consecutive_rejections_ = 0;
    const KalmanGain gain = kalman_gain(state.P, H, noise, nullptr);
    if (gain.ok && apply_update(state, gain, r)) ++report.fused;
  }
  kernel.record().detail_json =
      fmt::format(R"({{"aligned":true,"fused":{},"rejected":{}}})", report.fused, report.rejected);
  return report;
}

}  // namespace edx::backend::vio
