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
  // The estimate (yaw, t) = g depends on the fixes' noise and on the filter's error over the
  // batch. The latter is taken as the 4-DoF motion (yaw alpha about the filter's origin, shift
  // delta) of the current antenna a: dtheta_z = alpha, da = dp - [R_WI l]x dtheta = alpha
  // [e_z]x a + delta, which the alignment absorbs: dyaw = -alpha, dt = -Rz delta. Hence
  // dg = G dx + n with
  //   G_yaw = -e_z^T on dtheta,   G_t = -Rz on dp,  Rz [R_WI l]x + Rz [e_z]x a e_z^T on dtheta,
  // and P <- [P, P G^T; G P, G P G^T + N]: the frames keep their correlation with the pose
  // (fixes constrain p + t, which was aligned, not p alone). G N_x equals the GPS-frame part of
  // the unobservable directions (yaw: -1, 0; translation: 0, -Rz), so no spurious information.
  // N: var(yaw) = sigma^2 / sum_i |e_i,xy|^2 (e_i the centred fixes); t = mean_G - Rz mean_W:
  // var(t) = sigma^2/n I + lever var_yaw lever^T, cov(t, yaw) = -lever var_yaw.
  const double var_yaw = sigma2 / spread;
  const Eigen::Vector3d mean_w = est.rowwise().mean();
  const Eigen::Vector3d lever = skew(Eigen::Vector3d::UnitZ()) * T.rotation * mean_w;
  constexpr int kG = kGpsYaw;  // yaw_GV, t_GV: 4 consecutive error states
  const int n = state.dim();
  const Eigen::Matrix3d Rz = T.rotation;
  const Eigen::Vector3d arm = state.R_WI * options_.gps_lever_arm_m;
  const Eigen::Vector3d a = state.p_lin() + arm;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(4, n);
  G(0, kTheta + 2) = -1;
  G.block<3, 3>(1, kPos) = -Rz;
  G.block<3, 3>(1, kTheta) = Rz * skew(arm);
  G.block<3, 1>(1, kTheta + 2) += Rz * skew(Eigen::Vector3d::UnitZ()) * a;
  state.P.middleRows<4>(kG).setZero();
  state.P.middleCols<4>(kG).setZero();
  const Eigen::MatrixXd GP = G * state.P;
  Eigen::Matrix4d noise = Eigen::Matrix4d::Zero();
  noise(0, 0) = var_yaw;
  noise.block<3, 3>(1, 1) = sigma2 / static_cast<double>(count) * Eigen::Matrix3d::Identity() +
                            var_yaw * lever * lever.transpose();
  noise.block<3, 1>(1, 0) = -var_yaw * lever;
  noise.block<1, 3>(0, 1) = -var_yaw * lever.transpose();
  state.P.middleRows<4>(kG) = GP;
  state.P.middleCols<4>(kG) = GP.transpose();
  state.P.block<4, 4>(kG, kG) = GP * G.transpose() + noise;
  state.yaw_GV_fe = state.yaw_GV;
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
  // Rows fused per fix: the horizontal position (x, y in G), and the height with
  // gps_fuse_vertical (default). Each row of H keeps H N = 0 (FEJ), so dropping the height row
  // adds no information along the unobservable directions either.
  const int rows = options_.gps_fuse_vertical ? 3 : 2;
  const double gate = chi2_quantile(options_.gps_chi2_confidence, rows);
  for (const auto& fix : fixes) {
    const int n = state.dim();
    const double sigma = std::max(fix.sigma_m, options_.gps_sigma_floor_m);
    const double dt = static_cast<double>(state.t_ns - fix.t_ns) * 1e-9;
    const Eigen::Matrix3d Rz =
        Eigen::AngleAxisd(state.yaw_GV, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d a = antenna(fix);
    // First-estimate Jacobians: yaw_GV at its alignment value, and H_yaw = H N_yaw's remainder
    // with p, v at their first estimates, so that H N = 0 for the 4 unobservable directions.
    const Eigen::Matrix3d Rz_fe =
        Eigen::AngleAxisd(state.yaw_GV_fe.value_or(state.yaw_GV), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    const Eigen::Vector3d arm = state.R_WI * lever;
    const Eigen::Vector3d a_fe = state.p_lin() + arm - state.v_lin() * dt;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, n);
    H.block<3, 3>(0, kTheta) = -Rz_fe * skew(arm);
    H.block<3, 3>(0, kPos) = Rz_fe;
    H.block<3, 3>(0, kVel) = -dt * Rz_fe;
    H.block<3, 1>(0, kGpsYaw) = Rz_fe * skew(Eigen::Vector3d::UnitZ()) * a_fe;
    H.block<3, 3>(0, kGpsPos).setIdentity();
    H.conservativeResize(rows, Eigen::NoChange);
    const Eigen::VectorXd r = (fix.position_m - (Rz * a + state.t_GV)).head(rows);
    const Eigen::VectorXd noise = Eigen::VectorXd::Constant(rows, sigma * sigma);
    Eigen::MatrixXd S = H * state.P * H.transpose();
    S.diagonal() += noise;
    const double gamma = r.dot(S.ldlt().solve(r));
    if (gamma > gate && consecutive_rejections_ < 20) {
      ++report.rejected;
      ++consecutive_rejections_;
      continue;
    }
    consecutive_rejections_ = 0;
    const KalmanGain gain = kalman_gain(state.P, H, noise, &recorder, options_.precision);
    if (gain.ok && apply_update(state, gain, r, &recorder, options_.precision)) ++report.fused;
  }
  kernel.record().detail_json =
      fmt::format(R"({{"aligned":true,"fused":{},"rejected":{}}})", report.fused, report.rejected);
  return report;
}

}  // namespace edx::backend::vio
