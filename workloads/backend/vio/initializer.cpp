#include "workloads/backend/vio/initializer.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <map>

#include "workloads/backend/pnp_ransac.hpp"
#include "workloads/backend/vio/vio_state.hpp"

namespace edx::backend::vio {
namespace {

/// Gyro/accelerometer integration in the frame of the first sample's body, for a gyro bias b.
struct Preintegrated {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< I0 <- I(t)
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();  ///< double integral of R a
  Eigen::Vector3d beta = Eigen::Vector3d::Zero();   ///< single integral of R a
  /// dR/db: R(b + db) = R(b) Exp(D db), D <- Exp(w dt)^T D - I dt per step (the right Jacobian
  /// of a step's small rotation taken as I).
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
};

}  // namespace

Initializer::Initializer(const VioOptions& options, const Eigen::Isometry3d& T_body_left,
                         double focal_px)
    : options_(options), T_body_left_(T_body_left), focal_px_(focal_px) {}

std::optional<InitialState> Initializer::add_frame(std::int64_t t_ns,
                                                   std::span<const datasets::ImuSample> imu,
                                                   std::vector<FrameFeature> features) {
  for (const auto& s : imu)
    if (imu_.empty() || s.t_ns > imu_.back().t_ns) imu_.push_back(s);
  frames_.push_back({t_ns, std::move(features)});
  if (static_cast<int>(frames_.size()) < options_.init_frames) {
    reason_ = "gathering frames";
    return std::nullopt;
  }
  std::optional<InitialState> state = try_static();
  if (!state) state = try_moving();
  if (!state) {
    frames_.erase(frames_.begin());
    const std::int64_t t0 = frames_.front().t_ns;
    std::erase_if(imu_, [&](const datasets::ImuSample& s) { return s.t_ns < t0 - 100'000'000; });
  }
  return state;
}

std::optional<InitialState> Initializer::try_static() {
  const std::int64_t t0 = frames_.front().t_ns, t1 = frames_.back().t_ns;
  Eigen::Vector3d accel_sum = Eigen::Vector3d::Zero(), gyro_sum = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> accels;
  for (const auto& s : imu_) {
    if (s.t_ns < t0 || s.t_ns > t1) continue;
    accels.push_back(s.accel_m_s2);
    accel_sum += s.accel_m_s2;
    gyro_sum += s.gyro_rad_s;
  }
  if (accels.size() < 2) {
    reason_ = "too few IMU samples";
    return std::nullopt;
  }
  const double count = static_cast<double>(accels.size());
  const Eigen::Vector3d accel_mean = accel_sum / count;
  Eigen::Vector3d var = Eigen::Vector3d::Zero();
  for (const auto& a : accels) var += (a - accel_mean).cwiseAbs2();
  const double accel_sd = std::sqrt((var / (count - 1)).maxCoeff());
  // Mean pixel motion of the tracks between the first and the last frame.
  std::map<std::int64_t, Eigen::Vector2d> first;
  for (const FrameFeature& f : frames_.front().features) first[f.id] = f.observation.left;
  double motion = 0;
  int common = 0;
  for (const FrameFeature& f : frames_.back().features) {
    const auto it = first.find(f.id);
    if (it == first.end()) continue;
    motion += (f.observation.left - it->second).norm() * focal_px_;
    ++common;
  }
  if (common == 0) {
    reason_ = "no tracks across the initialization frames";
    return std::nullopt;
  }
  motion /= common;
  if (accel_sd > options_.static_max_accel_sd || motion > options_.static_max_pixel_motion) {
    reason_ =
        fmt::format("moving (accel SD {:.3f} m/s^2, track motion {:.2f} px)", accel_sd, motion);
    return std::nullopt;
  }
  InitialState state;
  state.t_ns = t1;
  state.static_start = true;
  // At rest the accelerometer reads R_WI^T (0, 0, g): R_WI maps its direction onto +z.
  state.R_WI = Eigen::Quaterniond::FromTwoVectors(accel_mean.normalized(), Eigen::Vector3d::UnitZ())
                   .toRotationMatrix();
  state.gyro_bias = gyro_sum / count;
  return state;
}

std::optional<std::vector<Eigen::Isometry3d>> Initializer::chained_pnp_poses() {
  const Eigen::Isometry3d T_IC = T_body_left_;
  // Each step uses the nearest, freshest stereo points. PnP of every frame against frame 0's
  // points alone would reference all of them to one set of stereo depths: on a street with a
  // 0.11 m baseline their depth errors (a few % at 10-30 m, the points changing as the car closes
  // in on them) gave position errors of up to 0.24 m within 1 s, hence gravity 0.8 m/s^2
  // (0.08 rad) and velocity 0.6-0.9 m/s off (6-9 sigma of the prior, docs/VIO.md).
  const int n = static_cast<int>(frames_.size()) - 1;
  std::vector<Eigen::Isometry3d> T_I0_I(frames_.size(), Eigen::Isometry3d::Identity());
  Eigen::Isometry3d T_Ck_C0 = Eigen::Isometry3d::Identity();
  for (int k = 1; k <= n; ++k) {
    // Stereo points of frame k-1 in its left camera.
    std::map<std::int64_t, Eigen::Vector3d> points;
    for (const FrameFeature& f : frames_[static_cast<std::size_t>(k - 1)].features) {
      if (f.depth_m <= 0) continue;
      points[f.id] = f.depth_m * Eigen::Vector3d(f.observation.left.x(), f.observation.left.y(), 1);
    }
    std::vector<Eigen::Vector3d> object;
    std::vector<Eigen::Vector2d> image;
    for (const FrameFeature& f : frames_[static_cast<std::size_t>(k)].features) {
      const auto it = points.find(f.id);
      if (it == points.end()) continue;
      object.push_back(it->second);
      image.push_back(f.observation.left);
    }
    if (object.size() < 12) {
      reason_ = fmt::format("only {} stereo points of frame {} tracked into frame {}",
                            object.size(), k - 1, k);
      return std::nullopt;
    }
    // Normalized image coordinates (K = I): the 2 px threshold over the focal length.
    const std::optional<PnpSolution> step = pnp_ransac(object, image, PnpIntrinsics{},
                                                       {.iterations = 200,
                                                        .reprojection_threshold = 2.0 / focal_px_,
                                                        .confidence = 0.99,
                                                        .method = PnpMethod::kIterative});
    if (!step || step->inliers.size() < 10) {
      reason_ = "PnP failed on the initialization frames";
      return std::nullopt;
    }
    const Eigen::Isometry3d& T_step = step->T_cam_object;  // C_k <- C_k-1
    T_Ck_C0 = T_step * T_Ck_C0;
    T_I0_I[static_cast<std::size_t>(k)] = T_IC * T_Ck_C0.inverse() * T_IC.inverse();
  }
  return T_I0_I;
}

std::optional<InitialState> Initializer::try_moving() {
  const std::int64_t t0 = frames_.front().t_ns;
  // Preintegrates the IMU with gyro bias b at every frame time (empty when the samples do not
  // cover the frames).
  const auto preintegrate = [&](const Eigen::Vector3d& gyro_bias) {
    std::vector<Preintegrated> at_frame(frames_.size());
    Preintegrated pre;
    std::size_t frame = 1;
    const datasets::ImuSample* previous = nullptr;
    for (const auto& s : imu_) {
      if (s.t_ns < t0) continue;
      if (previous) {
        const double dt = static_cast<double>(s.t_ns - previous->t_ns) * 1e-9;
        const Eigen::Vector3d w = 0.5 * (s.gyro_rad_s + previous->gyro_rad_s) - gyro_bias;
        const Eigen::Vector3d a = 0.5 * (s.accel_m_s2 + previous->accel_m_s2);
        const Eigen::Matrix3d R_step = so3_exp(w * dt);
        const Eigen::Matrix3d R_next = pre.R * R_step;
        const Eigen::Vector3d a0 = 0.5 * (pre.R + R_next) * a;
        pre.alpha += pre.beta * dt + 0.5 * a0 * dt * dt;
        pre.beta += a0 * dt;
        pre.R = R_next;
        pre.D = R_step.transpose() * pre.D - dt * Eigen::Matrix3d::Identity();
      }
      previous = &s;
      while (frame < frames_.size() && s.t_ns >= frames_[frame].t_ns) at_frame[frame++] = pre;
    }
    if (frame < frames_.size()) at_frame.clear();
    return at_frame;
  };
  const std::optional<std::vector<Eigen::Isometry3d>> visual = chained_pnp_poses();
  if (!visual) return std::nullopt;
  const std::vector<Eigen::Isometry3d>& T_I0_I = *visual;
  const int n = static_cast<int>(frames_.size()) - 1;
  // Gyro bias from the visual rotations (VINS-Mono's gyroscope bias calibration, Qin, Li & Shen,
  // T-RO 2018, Sec. V-B): R_0k(b) = R_0k(0) Exp(D_k b) should equal the PnP rotation R_0k^vis,
  // so b = argmin sum_k |Log(R_0k(b)^T R_0k^vis) - D_k db|^2, two Gauss-Newton steps. At rest or
  // moving, it replaces the prior's zero by what the window measures (EuRoC V1_01's ADIS16448
  // starts at 0.077 rad/s about z, 15 sigma of the 0.005 rad/s fallback prior).
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  std::vector<Preintegrated> at_frame;
  for (int iteration = 0; iteration < 3; ++iteration) {
    at_frame = preintegrate(gyro_bias);
    if (at_frame.empty()) {
      reason_ = "IMU samples do not cover the initialization frames";
      return std::nullopt;
    }
    if (iteration == 2) break;
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (int k = 1; k <= n; ++k) {
      const Preintegrated& p = at_frame[static_cast<std::size_t>(k)];
      const Eigen::Vector3d r =
          so3_log(p.R.transpose() * T_I0_I[static_cast<std::size_t>(k)].linear());
      normal += p.D.transpose() * p.D;
      rhs += p.D.transpose() * r;
    }
    gyro_bias += normal.ldlt().solve(rhs);
  }
  // Rows p_k - alpha_k = [t_k I, t_k^2/2 I] (v0, g0).
  Eigen::MatrixXd A(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(frames_[static_cast<std::size_t>(k)].t_ns - t0) * 1e-9;
    A.block(3 * (k - 1), 0, 3, 3) = t * Eigen::Matrix3d::Identity();
    A.block(3 * (k - 1), 3, 3, 3) = 0.5 * t * t * Eigen::Matrix3d::Identity();
    b.segment<3>(3 * (k - 1)) = T_I0_I[static_cast<std::size_t>(k)].translation() -
                                at_frame[static_cast<std::size_t>(k)].alpha;
  }
  const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
  Eigen::Vector3d g0 = x.tail<3>();
  const double g_norm = g0.norm();
  if (std::abs(g_norm - options_.gravity_m_s2) > 0.2 * options_.gravity_m_s2) {
    reason_ = fmt::format("gravity estimate {:.2f} m/s^2 off", g_norm);
    return std::nullopt;
  }
  g0 *= options_.gravity_m_s2 / g_norm;
  // v0 = sum_k t_k (p_k - alpha_k - g0 t_k^2/2) / sum_k t_k^2.
  Eigen::Vector3d num = Eigen::Vector3d::Zero();
  double den = 0;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(frames_[static_cast<std::size_t>(k)].t_ns - t0) * 1e-9;
    num += t * (b.segment<3>(3 * (k - 1)) - 0.5 * t * t * g0);
    den += t * t;
  }
  const Eigen::Vector3d v0 = num / den;
  const Eigen::Matrix3d R_W0 =
      Eigen::Quaterniond::FromTwoVectors(g0.normalized(), -Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const Preintegrated& last = at_frame.back();
  const double t_last = static_cast<double>(frames_.back().t_ns - t0) * 1e-9;
  InitialState state;
  state.t_ns = frames_.back().t_ns;
  state.R_WI = R_W0 * last.R;
  state.p_WI = R_W0 * T_I0_I.back().translation();
  state.v_WI = R_W0 * (v0 + g0 * t_last + last.beta);
  state.gyro_bias = gyro_bias;
  return state;
}

}  // namespace edx::backend::vio
