#include "workloads/backend/vio/imu_propagator.hpp"

#include <algorithm>

namespace edx::backend::vio {
namespace {

/// The reading at time t, linearly interpolated between two samples.
datasets::ImuSample interpolate(const datasets::ImuSample& a, const datasets::ImuSample& b,
                                std::int64_t t) {
  if (b.t_ns == a.t_ns) return b;
  const double s = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  datasets::ImuSample out;
  out.t_ns = t;
  out.gyro_rad_s = a.gyro_rad_s + s * (b.gyro_rad_s - a.gyro_rad_s);
  out.accel_m_s2 = a.accel_m_s2 + s * (b.accel_m_s2 - a.accel_m_s2);
  return out;
}

}  // namespace

ImuPropagator::ImuPropagator(const ImuNoiseDensities& noise, double gravity_m_s2)
    : noise_(noise), gravity_(0, 0, -gravity_m_s2) {}

void ImuPropagator::add(std::span<const datasets::ImuSample> samples) {
  for (const auto& s : samples) {
    if (buffer_.empty() || s.t_ns > buffer_.back().t_ns) buffer_.push_back(s);
  }
}

ImuInterval ImuPropagator::integrate(VioState& state, std::int64_t t_ns) {
  ImuInterval interval;
  if (buffer_.empty() || t_ns <= state.t_ns) {
    state.t_ns = std::max(state.t_ns, t_ns);
    return interval;
  }
  // Readings at the interval ends: interpolated at state.t_ns and t_ns (held constant beyond
  // the buffer), and every sample strictly between.
  std::vector<datasets::ImuSample> readings;
  const auto at = [&](std::int64_t t) {
    const auto it =
        std::lower_bound(buffer_.begin(), buffer_.end(), t,
                         [](const datasets::ImuSample& s, std::int64_t v) { return s.t_ns < v; });
    datasets::ImuSample out;
    if (it == buffer_.begin())
      out = buffer_.front();
    else if (it == buffer_.end())
      out = buffer_.back();
    else
      out = interpolate(*(it - 1), *it, t);
    out.t_ns = t;
    return out;
  };
  readings.push_back(at(state.t_ns));
  for (const auto& s : buffer_)
    if (s.t_ns > state.t_ns && s.t_ns < t_ns) readings.push_back(s);
  readings.push_back(at(t_ns));
  interval.propagated = true;

  // First estimates of the interval start (FEJ): the values propagated to it, before the
  // updates of that image.
  const Eigen::Vector3d p0_fe = state.p_lin(), v0_fe = state.v_lin();
  const std::int64_t t0_ns = state.t_ns;
  using Mat15 = ImuInterval::Mat15;
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  for (std::size_t k = 0; k + 1 < readings.size(); ++k) {
    const double dt = static_cast<double>(readings[k + 1].t_ns - readings[k].t_ns) * 1e-9;
    if (dt <= 0) continue;
    const Eigen::Vector3d w =
        0.5 * (readings[k].gyro_rad_s + readings[k + 1].gyro_rad_s) - state.gyro_bias;
    const Eigen::Vector3d a =
        0.5 * (readings[k].accel_m_s2 + readings[k + 1].accel_m_s2) - state.accel_bias;
    const Eigen::Matrix3d R = state.R_WI;
    const Eigen::Matrix3d R_next = R * so3_exp(w * dt);
    const Eigen::Vector3d a_world = 0.5 * (R + R_next) * a + gravity_;
    state.p_WI += state.v_WI * dt + 0.5 * a_world * dt * dt;
    state.v_WI += a_world * dt;
    state.R_WI = R_next;

    const Eigen::Matrix3d A = skew(R * a);
    Mat15 Phi = Mat15::Identity();
    Phi.block<3, 3>(kTheta, kGyroBias) = -R * dt;
    Phi.block<3, 3>(kPos, kVel) = I3 * dt;
    Phi.block<3, 3>(kPos, kTheta) = -0.5 * A * dt * dt;
    Phi.block<3, 3>(kPos, kAccelBias) = -0.5 * R * dt * dt;
    Phi.block<3, 3>(kVel, kTheta) = -A * dt;
    Phi.block<3, 3>(kVel, kAccelBias) = -R * dt;
    Mat15 Q = Mat15::Zero();
    const double sg2 = noise_.gyro_noise * noise_.gyro_noise,
                 sa2 = noise_.accel_noise * noise_.accel_noise;
    Q.block<3, 3>(kTheta, kTheta) = sg2 * dt * I3;
    Q.block<3, 3>(kVel, kVel) = sa2 * dt * I3;
    Q.block<3, 3>(kPos, kPos) = sa2 * dt * dt * dt / 3.0 * I3;
    Q.block<3, 3>(kPos, kVel) = sa2 * dt * dt / 2.0 * I3;
    Q.block<3, 3>(kVel, kPos) = sa2 * dt * dt / 2.0 * I3;
    Q.block<3, 3>(kGyroBias, kGyroBias) = noise_.gyro_walk * noise_.gyro_walk * dt * I3;
    Q.block<3, 3>(kAccelBias, kAccelBias) = noise_.accel_walk * noise_.accel_walk * dt * I3;
    interval.Phi.push_back(Phi);
    interval.Q.push_back(Q);
  }
  state.t_ns = t_ns;
  // First-estimate Jacobian of the whole interval T: the dtheta columns of dp and dv evaluated
  // so that the yaw direction of the unobservable subspace, N = (e_z, -[p]x e_z, -[v]x e_z),
  // propagates exactly, Phi N(p0_fe, v0_fe) = N(p1, v1):
  //   Phi_v,theta = -[v1 - v0_fe - g T]x,  Phi_p,theta = -[p1 - p0_fe - v0_fe T - g T^2/2]x.
  // (The per-sample product gives the same up to the linearization point of the interval start
  // and the first-order rotation of the specific force.)
  if (interval.steps() > 0) {
    const double T = static_cast<double>(t_ns - t0_ns) * 1e-9;
    interval.Phi_v_theta = -skew(state.v_WI - v0_fe - gravity_ * T);
    interval.Phi_p_theta = -skew(state.p_WI - p0_fe - v0_fe * T - 0.5 * gravity_ * T * T);
  }
  state.p_fe = state.p_WI;
  state.v_fe = state.v_WI;
  state.has_fe = true;
  // Samples before the new time are no longer needed (keep the last one before it).
  const auto keep =
      std::lower_bound(buffer_.begin(), buffer_.end(), t_ns,
                       [](const datasets::ImuSample& s, std::int64_t v) { return s.t_ns < v; });
  if (keep != buffer_.begin()) buffer_.erase(buffer_.begin(), keep - 1);
  return interval;
}

void ImuPropagator::propagate_covariance(VioState& state, const ImuInterval& interval,
                                         KernelRecorder* recorder) {
  if (!interval.propagated) return;
  using Mat15 = ImuInterval::Mat15;
  const int steps = interval.steps();
  Mat15 Phi_total = Mat15::Identity();
  Mat15 Q_total = Mat15::Zero();
  for (int k = 0; k < steps; ++k) {
    const Mat15& Phi = interval.Phi[static_cast<std::size_t>(k)];
    Phi_total = (Phi * Phi_total).eval();
    Q_total = (Phi * Q_total * Phi.transpose() + interval.Q[static_cast<std::size_t>(k)]).eval();
  }
  if (steps > 0) {  // the first-estimate blocks (integrate)
    Phi_total.block<3, 3>(kVel, kTheta) = interval.Phi_v_theta;
    Phi_total.block<3, 3>(kPos, kTheta) = interval.Phi_p_theta;
  }
  const int n = state.dim();
  const int rest = n - kImuDim;
  Eigen::MatrixXd& P = state.P;
  P.topLeftCorner<kImuDim, kImuDim>() =
      Phi_total * P.topLeftCorner<kImuDim, kImuDim>() * Phi_total.transpose() + Q_total;
  if (rest > 0) {
    P.topRightCorner(kImuDim, rest) = (Phi_total * P.topRightCorner(kImuDim, rest)).eval();
    P.bottomLeftCorner(rest, kImuDim) = P.topRightCorner(kImuDim, rest).transpose();
  }
  state.symmetrize();
  if (recorder != nullptr) {
    // Per step Φ Φ_total and Φ Q_total Φᵀ (3 gemm 15x15x15, the last symmetric); then
    // Φ P_II Φᵀ (2 gemm), Φ P_IR (gemm 15 x rest x 15), P_RI = P_IRᵀ and the symmetrization.
    namespace f = trace::op_flags;
    using trace::Op;
    if (steps > 0) {
      recorder->describe(Op::Gemm, kImuDim, kImuDim, kImuDim, 0, 2 * steps);
      recorder->describe(Op::Gemm, kImuDim, kImuDim, kImuDim, f::kSymmetric | f::kTransposeB,
                         steps);
    }
    recorder->describe(Op::Gemm, kImuDim, kImuDim, kImuDim, 0);
    recorder->describe(Op::Gemm, kImuDim, kImuDim, kImuDim, f::kSymmetric | f::kTransposeB);
    if (rest > 0) {
      recorder->describe(Op::Gemm, kImuDim, rest, kImuDim, 0);
      recorder->describe(Op::Transpose, kImuDim, rest, 0, 0);
    }
    recorder->describe(Op::Transpose, n, n, 0, 0);
  }
}

int ImuPropagator::propagate(VioState& state, std::int64_t t_ns) {
  const ImuInterval interval = integrate(state, t_ns);
  propagate_covariance(state, interval, nullptr);
  return interval.steps();
}

}  // namespace edx::backend::vio
