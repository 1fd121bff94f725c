// Unit tests of the VIO backend's pieces against hand-computed or independently known values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include "tests/workloads/backend/vio/vio_run.hpp"
#include "tests/workloads/frontend/plane_scene.hpp"
#include "workloads/backend/vio/chi_square.hpp"
#include "workloads/backend/vio/ekf_update.hpp"
#include "workloads/backend/vio/gps_fusion.hpp"
#include "workloads/backend/vio/imu_propagator.hpp"
#include "workloads/backend/vio/initializer.hpp"
#include "workloads/backend/vio/msckf_updater.hpp"
#include "workloads/backend/vio/track_noise.hpp"
#include "workloads/backend/vio/triangulation.hpp"
#include "workloads/backend/vio/vio_backend.hpp"
#include "workloads/backend/vio/vio_options.hpp"
#include "workloads/backend/vio/vio_state.hpp"

namespace edx::backend::vio {
namespace {

// Quantiles from standard chi-square tables.
TEST(ChiSquare, QuantilesMatchTables) {
  EXPECT_NEAR(chi2_quantile(0.95, 1), 3.841459, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.95, 2), 5.991465, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.95, 3), 7.814728, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.95, 10), 18.307038, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.95, 100), 124.342113, 1e-4);
  EXPECT_NEAR(chi2_quantile(0.025, 6), 1.237344, 1e-5);
  EXPECT_NEAR(chi2_quantile(0.975, 6), 14.449375, 1e-5);
  EXPECT_NEAR(chi2_survival(2.0, 2), std::exp(-1.0), 1e-12);  // Q = exp(-x/2) for k = 2
}

// validate() throws a message naming `field` for options with one bad field.
void expect_rejected_naming(const VioOptions& options, const std::string& field) {
  try {
    options.validate();
    ADD_FAILURE() << "expected a throw naming " << field;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(VioOptions, ValidateNamesTheField) {
  EXPECT_NO_THROW(VioOptions{}.validate());
  const auto with = [](auto change) {
    VioOptions options;
    change(options);
    return options;
  };
  expect_rejected_naming(with([](VioOptions& o) { o.max_clones = 1; }), "max_clones");
  EXPECT_EQ(VioOptions{}.to_json().at("max_clones"), 30);
  // rho = 1 would give the measurements no information.
  expect_rejected_naming(with([](VioOptions& o) { o.track_error_correlation = 1.0; }),
                         "track_error_correlation");
  // A zero disparity sigma would make the track covariance singular; a negative sd means nothing.
  expect_rejected_naming(with([](VioOptions& o) { o.random_walk.disparity_sigma_px = 0; }),
                         "random_walk.disparity_sigma_px");
  expect_rejected_naming(with([](VioOptions& o) { o.random_walk.step_scale_px = -1; }),
                         "random_walk.step_scale_px");
  // 0 turns the first-window check off; below that means nothing.
  expect_rejected_naming(with([](VioOptions& o) { o.first_window_check_px = -1; }),
                         "first_window_check_px");
  expect_rejected_naming(with([](VioOptions& o) { o.first_window_half_px = 2; }),
                         "first_window_half_px");
  EXPECT_EQ(VioOptions{}.to_json().at("first_window_check_px"), 0.0);  // off by default
  EXPECT_EQ(VioOptions{}.to_json().at("track_noise"), "random_walk");
  EXPECT_EQ(VioOptions{}.to_json().at("random_walk").at("step_scale_px"), 3.7);
}

// sigma sqrt((1 + rho) / (1 - rho)): rho 0.8 -> sqrt(1.8 / 0.2) = 3; rho 0 -> white noise.
TEST(VioOptions, EffectivePixelSigmaInflatesForTrackCorrelation) {
  VioOptions options;
  options.pixel_sigma = 1.0;
  options.track_error_correlation = 0.8;
  EXPECT_NEAR(options.effective_pixel_sigma(), 3.0, 1e-12);
  options.pixel_sigma = 0.5;
  options.track_error_correlation = 0.6;  // sqrt(1.6 / 0.4) = 2
  EXPECT_NEAR(options.effective_pixel_sigma(), 1.0, 1e-12);
  options.track_error_correlation = 0;
  EXPECT_DOUBLE_EQ(options.effective_pixel_sigma(), 0.5);
}

// The first-window check: twelve tracks follow a textured image sliding 2 px a frame; one of
// them is reported 0.3 px a frame further (a drifting track), so it is 1.2 px off its point at
// frame 4, where the check (1 px) ends it; the others stay. Checked through the track_check
// kernel the backend records: windows cut, observations checked, tracks ended.
TEST(VioBackend, FirstWindowCheckEndsTheDriftingTrack) {
  BackendCamera camera;
  camera.width = 640;
  camera.height = 400;
  camera.fx = camera.fy = 400;
  camera.cx = 320;
  camera.cy = 200;
  camera.baseline_m = 0.1;
  datasets::ImuNoise noise;
  noise.gyro_noise_density = 1.7e-4;
  noise.gyro_random_walk = 1.9e-5;
  noise.accel_noise_density = 2.0e-3;
  noise.accel_random_walk = 3.0e-3;
  frontend::testing::PlaneScene scene;
  scene.texture = frontend::testing::make_texture({1000, 700}, 31);
  // Twelve textured points (an aligned window found where it is).
  std::vector<cv::Point2f> points;
  for (int y = 100; y < 300 && points.size() < 12; y += 37) {
    for (int x = 100; x < 500 && points.size() < 12; x += 53) {
      const cv::Point2f p(static_cast<float>(x), static_cast<float>(y));
      const cv::Mat prepared = frontend::FirstWindow::prepare(scene.left());
      if (frontend::FirstWindow(prepared, p, 10).align(prepared, p, 30, 0.01)) {
        points.push_back(p);
      }
    }
  }
  ASSERT_EQ(points.size(), 12u);
  const auto run = [&](const VioOptions& options) {
    VioBackend backend(camera, noise, options);
    std::vector<trace::KernelRecord> checks;
    for (int k = 0; k <= 6; ++k) {
      const cv::Mat image = scene.left({2.0 * k, 0});
      frontend::FrontendFrame frame;
      for (std::size_t i = 0; i < points.size(); ++i) {
        frontend::Feature f;
        f.id = static_cast<std::int64_t>(i);
        f.age = k;
        f.left = points[i] + cv::Point2f(2.0f * static_cast<float>(k), 0);
        if (i == 5) f.left.x += 0.3f * static_cast<float>(k);  // drifts 0.3 px a frame
        frame.features.push_back(f);
      }
      BackendInput input;
      input.t_ns = 50'000'000LL * k;
      input.frontend = &frame;
      input.left_image = &image;
      for (const trace::KernelRecord& kernel : backend.process(input).kernels) {
        if (kernel.kernel == "track_check") checks.push_back(kernel);
      }
    }
    return checks;
  };
  VioOptions on;
  on.first_window_check_px = 1.0;
  const std::vector<trace::KernelRecord> checks = run(on);
  ASSERT_EQ(checks.size(), 7u);
  EXPECT_EQ(checks[0].n, 12);  // windows cut
  EXPECT_EQ(checks[0].m, 0);
  for (int k = 1; k <= 6; ++k) {
    SCOPED_TRACE(k);
    const nlohmann::json detail = nlohmann::json::parse(checks[k].detail_json);
    EXPECT_EQ(checks[k].n, 0);
    EXPECT_EQ(checks[k].m, k <= 4 ? 12 : 11);  // the ended track is not checked again
    EXPECT_EQ(detail.at("ended"), k == 4 ? 1 : 0);
    EXPECT_GT(detail.at("iterations"), 0);
  }
  EXPECT_TRUE(run(VioOptions{}).empty());  // off by default: no track_check kernel
}

// Bias priors: the option when set, else the IMU file's stated turn-on bias, else the fallback.
TEST(VioBackend, BiasPriorsComeFromOptionThenImuFileThenFallback) {
  VioOptions options;
  datasets::ImuNoise noise;  // EuRoC-like: no turn-on bias stated
  auto priors = VioBackend::bias_priors(options, noise);
  EXPECT_EQ(priors.gyro, VioOptions::kFallbackGyroBiasSigma);
  EXPECT_EQ(priors.accel, VioOptions::kFallbackAccelBiasSigma);
  noise.gyro_bias_sigma = 0.002;
  noise.accel_bias_sigma = 0.02;
  priors = VioBackend::bias_priors(options, noise);
  EXPECT_EQ(priors.gyro, 0.002);
  EXPECT_EQ(priors.accel, 0.02);
  options.init_accel_bias_sigma = 0.07;
  priors = VioBackend::bias_priors(options, noise);
  EXPECT_EQ(priors.gyro, 0.002);
  EXPECT_EQ(priors.accel, 0.07);
  EXPECT_EQ(options.to_json().at("init_accel_bias_sigma"), 0.07);
  EXPECT_EQ(options.to_json().at("init_gyro_bias_sigma"), "from dataset");
}

TEST(VioState, CloningThenMarginalizingRestoresTheCovariance) {
  VioState state;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd A(kCoreDim, kCoreDim);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = normal(rng);
  state.P = A * A.transpose();
  const Eigen::MatrixXd P0 = state.P;
  state.augment_clone();
  ASSERT_EQ(state.dim(), kCoreDim + kCloneDim);
  // The clone is a copy of (theta, p): its block and cross terms equal those of the pose.
  EXPECT_TRUE(state.P.block(kCoreDim, kCoreDim, 6, 6).isApprox(P0.topLeftCorner(6, 6)));
  EXPECT_TRUE(state.P.block(kCoreDim, 0, 6, kCoreDim).isApprox(P0.topRows(6)));
  state.augment_clone();
  state.marginalize_clone(0);
  state.marginalize_clone(0);
  EXPECT_TRUE(state.P.isApprox(P0));
  EXPECT_TRUE(state.clones.empty());
}

TEST(ImuPropagator, NoiseFreeMotionAndCovarianceGrowth) {
  const double g = 9.81, sa = 2e-3, sg = 1.7e-4;
  ImuPropagator propagator({sg, sa, 0.0, 0.0}, g);  // no bias walk: closed forms below
  std::vector<datasets::ImuSample> samples;
  // Free fall (zero specific force) while turning about z at 0.5 rad/s for 1 s, 200 Hz.
  for (int k = 0; k <= 200; ++k) {
    datasets::ImuSample s;
    s.t_ns = k * 5'000'000;
    s.gyro_rad_s = {0, 0, 0.5};
    samples.push_back(s);
  }
  propagator.add(samples);
  VioState state;
  state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
  state.v_WI = {1, 0, 0};
  EXPECT_EQ(propagator.propagate(state, 1'000'000'000), 200);
  EXPECT_NEAR(state.p_WI.x(), 1.0, 1e-9);
  EXPECT_NEAR(state.p_WI.z(), -0.5 * g, 1e-9);  // p = v t + g t^2 / 2
  EXPECT_NEAR(state.v_WI.z(), -g, 1e-9);
  EXPECT_NEAR(std::atan2(state.R_WI(1, 0), state.R_WI(0, 0)), 0.5, 1e-9);
  // With no specific force, attitude errors do not reach v and p: var(v) = sa^2 t,
  // var(p) = sa^2 t^3 / 3 per axis, var(theta) = sg^2 t.
  EXPECT_NEAR(state.P(kVel + 2, kVel + 2), sa * sa, 1e-12);
  EXPECT_NEAR(state.P(kPos + 2, kPos + 2), sa * sa / 3.0, 1e-12);
  EXPECT_NEAR(state.P(kTheta, kTheta), sg * sg, 1e-14);
}

// First-estimate Jacobians: with the interval start's first estimates (p0, v0) differing from
// the current (updated) estimate, the propagated covariance of the yaw direction
// N(p, v) = (e_z, [e_z]x p, [e_z]x v, 0, ...) must be N(p1, v1) N(p1, v1)^T exactly: Phi maps
// the unobservable direction at the first estimates onto the one at the propagated estimate.
TEST(ImuPropagator, FirstEstimateJacobianPropagatesTheYawNullSpace) {
  ImuPropagator propagator({0.0, 0.0, 0.0, 0.0}, 9.81);  // noise free: P = Phi P Phi^T
  std::vector<datasets::ImuSample> samples;
  for (int k = 0; k <= 40; ++k) {  // 0.2 s, accelerating and turning about all axes
    datasets::ImuSample s;
    s.t_ns = k * 5'000'000;
    s.gyro_rad_s = {0.3, -0.2, 0.5 + 0.01 * k};
    s.accel_m_s2 = {1.0 + 0.05 * k, -0.5, 9.81 + 0.3};
    samples.push_back(s);
  }
  propagator.add(samples);
  VioState state;
  state.R_WI = so3_exp(Eigen::Vector3d(0.1, -0.05, 0.7));
  state.p_WI = {3, -2, 1};
  state.v_WI = {2, 1, 0.2};
  state.p_fe = {3.3, -2.1, 0.9};  // the estimates before the last update
  state.v_fe = {1.8, 1.3, 0.1};
  state.has_fe = true;
  const auto yaw_direction = [](const Eigen::Vector3d& p, const Eigen::Vector3d& v) {
    Eigen::VectorXd N = Eigen::VectorXd::Zero(kCoreDim);
    N(kTheta + 2) = 1;
    N.segment<3>(kPos) = Eigen::Vector3d::UnitZ().cross(p);
    N.segment<3>(kVel) = Eigen::Vector3d::UnitZ().cross(v);
    return N;
  };
  const Eigen::VectorXd N0 = yaw_direction(state.p_fe, state.v_fe);
  state.P = N0 * N0.transpose();
  propagator.propagate(state, 200'000'000);
  const Eigen::VectorXd N1 = yaw_direction(state.p_WI, state.v_WI);
  EXPECT_LT((state.P - N1 * N1.transpose()).norm(), 1e-9 * N1.squaredNorm());
  // The first estimates of the next interval are the propagated values.
  EXPECT_EQ(state.p_fe, state.p_WI);
  EXPECT_EQ(state.v_fe, state.v_WI);
}

TEST(EkfUpdate, GainMatchesTheClosedFormAndRecordsItsOps) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  const int n = 12, m = 5;
  Eigen::MatrixXd A(n, n), H(m, n);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = normal(rng);
  for (int i = 0; i < H.size(); ++i) H.data()[i] = normal(rng);
  const Eigen::MatrixXd P = A * A.transpose() + Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd noise = Eigen::VectorXd::Constant(m, 0.3);
  KernelRecorder recorder;
  KalmanGain gain;
  {
    auto kernel = recorder.kernel("kalman_gain", true);
    gain = kalman_gain(P, H, noise, &recorder);
  }
  ASSERT_TRUE(gain.ok);
  const Eigen::MatrixXd S = H * P * H.transpose() + Eigen::MatrixXd(noise.asDiagonal());
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  EXPECT_TRUE(gain.K.isApprox(K, 1e-10));
  const auto kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 1u);
  const auto& ops = kernels[0].ops;
  ASSERT_EQ(ops.size(), 6u);
  EXPECT_EQ(ops[0].op, trace::Op::Gemm);
  EXPECT_EQ(ops[1].op, trace::Op::Gemm);
  EXPECT_EQ(ops[1].m, m);
  EXPECT_EQ(ops[1].n, m);
  EXPECT_EQ(ops[1].k, n);
  EXPECT_TRUE(ops[1].flags & trace::op_flags::kSymmetric);
  EXPECT_EQ(ops[2].op, trace::Op::Potrf);
  EXPECT_EQ(ops[2].m, m);
  EXPECT_EQ(ops[3].op, trace::Op::Trsm);
  EXPECT_EQ(ops[3].n, n);
  EXPECT_EQ(ops[4].op, trace::Op::Trsm);
  EXPECT_EQ(ops[5].op, trace::Op::Transpose);
  // Covariance update P - K S K^T.
  VioState state;
  state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
  state.P.topLeftCorner(n, n) = P;
  const Eigen::MatrixXd H_full = [&] {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m, kCoreDim);
    h.leftCols(n) = H;
    return h;
  }();
  const KalmanGain full = kalman_gain(state.P, H_full, noise, nullptr);
  ASSERT_TRUE(apply_update(state, full, Eigen::VectorXd::Zero(m), nullptr));
  const Eigen::MatrixXd expected = P - K * S * K.transpose();
  EXPECT_TRUE(state.P.topLeftCorner(n, n).isApprox(expected, 1e-9));
  EXPECT_TRUE(state.P.isApprox(state.P.transpose()));
}

CameraPose camera_at(const Eigen::Vector3d& position, double yaw) {
  CameraPose c;
  c.R_WC = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  c.p_WC = position;
  return c;
}

Observation observe(const CameraPose& c, const Eigen::Vector3d& p_W, double baseline, bool stereo) {
  const Eigen::Vector3d p_C = c.R_WC.transpose() * (p_W - c.p_WC);
  Observation o;
  o.left = p_C.head<2>() / p_C.z();
  o.stereo = stereo;
  o.right_x = (p_C.x() - baseline) / p_C.z();
  return o;
}

/// Four views of `point` from cameras 0.3 m apart along x (and a little y, z, yaw), stereo in
/// the even views, or in all of them.
void four_views(const Eigen::Vector3d& point, double b, bool all_stereo,
                std::vector<CameraPose>& cameras, std::vector<Observation>& observations) {
  for (int i = 0; i < 4; ++i) {
    cameras.push_back(camera_at({0.3 * i, 0.05 * i, 0.1 * i}, 0.03 * i));
    observations.push_back(observe(cameras.back(), point, b, all_stereo || i % 2 == 0));
  }
}

// At fp32 the gain and the covariance update compute in single: the result agrees with the
// double one to single's precision (relative 1e-4 on this well-conditioned system, about
// n · 2^-24 · cond) but not to double's, and records the same ops.
TEST(EkfUpdate, Fp32ComputesInSinglePrecision) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const int n = 15, m = 6;
  Eigen::MatrixXd A(n, n), H(m, n);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = normal(rng);
  for (int i = 0; i < H.size(); ++i) H.data()[i] = normal(rng);
  const Eigen::MatrixXd P = A * A.transpose() + Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd noise = Eigen::VectorXd::Constant(m, 0.5);
  KernelRecorder recorder;
  KalmanGain g64, g32;
  {
    auto kernel = recorder.kernel("kalman_gain", true);
    g64 = kalman_gain(P, H, noise, &recorder, trace::Precision::kFp64);
  }
  {
    auto kernel = recorder.kernel("kalman_gain", true);
    g32 = kalman_gain(P, H, noise, &recorder, trace::Precision::kFp32);
  }
  ASSERT_TRUE(g64.ok && g32.ok);
  const double relative = (g32.K - g64.K).norm() / g64.K.norm();
  EXPECT_LT(relative, 1e-4);
  EXPECT_GT(relative, 1e-12);  // not double's arithmetic
  // Every entry of the fp32 gain is a float (widened exactly).
  for (Eigen::Index i = 0; i < g32.K.size(); ++i) {
    EXPECT_EQ(g32.K.data()[i], static_cast<double>(static_cast<float>(g32.K.data()[i])));
  }
  const auto kernels = recorder.take();
  ASSERT_EQ(kernels.size(), 2u);
  ASSERT_EQ(kernels[0].ops.size(), kernels[1].ops.size());
  for (std::size_t i = 0; i < kernels[0].ops.size(); ++i) {
    EXPECT_EQ(kernels[0].ops[i].op, kernels[1].ops[i].op);
  }
  Eigen::MatrixXd P64 = P, P32 = P;
  ASSERT_TRUE(update_covariance(P64, g64, nullptr, trace::Precision::kFp64));
  ASSERT_TRUE(update_covariance(P32, g32, nullptr, trace::Precision::kFp32));
  const double p_relative = (P32 - P64).norm() / P64.norm();
  EXPECT_LT(p_relative, 1e-4);
  EXPECT_GT(p_relative, 1e-12);
  EXPECT_TRUE(P32.isApprox(P32.transpose(), 0));  // still symmetric
}

TEST(Triangulation, RecoversAKnownPointAndRejectsBadGeometry) {
  const double b = 0.11;
  const Eigen::Vector3d point(0.7, -0.4, 6.0);
  std::vector<CameraPose> cameras;
  std::vector<Observation> observations;
  four_views(point, b, false, cameras, observations);
  // Start away from the truth: corrupt the stereo disparity of the first view (the initial guess).
  observations[0].right_x -= 0.002;
  TriangulationOptions options;
  options.baseline_m = b;
  options.max_rms = 1e-2;
  const auto result = triangulate(observations, cameras, options);
  ASSERT_TRUE(result);
  EXPECT_LT((result->p_W - point).norm(), 0.05);  // only the corrupted row disagrees
  // Without the corrupted row the point is exact.
  observations[0] = observe(cameras[0], point, b, true);
  const auto exact = triangulate(observations, cameras, options);
  ASSERT_TRUE(exact);
  EXPECT_LT((exact->p_W - point).norm(), 1e-8);
  EXPECT_LT(exact->rms, 1e-10);
  // Depth limits: the point lies beyond max_depth.
  options.max_depth_m = 5.0;
  EXPECT_FALSE(triangulate(observations, cameras, options));
}

TEST(Triangulation, RejectsPointsFarForTheirBaseline) {
  // Depth 6 m in the first view; the farthest centre that saw it is the last view's right camera,
  // (0.9, 0.15, 0.3) + R_WC (0.11, 0, 0) at 1.061 m from the first: ratio 5.65.
  const double b = 0.11;
  const Eigen::Vector3d point(0.7, -0.4, 6.0);
  std::vector<CameraPose> cameras;
  std::vector<Observation> observations;
  four_views(point, b, true, cameras, observations);
  TriangulationOptions options;
  options.baseline_m = b;
  options.max_rms = 1e-2;
  options.max_baseline_ratio = 5.8;
  EXPECT_TRUE(triangulate(observations, cameras, options));
  options.max_baseline_ratio = 5.5;
  EXPECT_FALSE(triangulate(observations, cameras, options));
  // One stereo view alone: the baseline is the stereo baseline, 6 / 0.11 = 54.5.
  const std::vector<Observation> one(observations.begin(), observations.begin() + 1);
  const std::vector<CameraPose> one_camera(cameras.begin(), cameras.begin() + 1);
  options.max_baseline_ratio = 55.0;
  EXPECT_TRUE(triangulate(one, one_camera, options));
  options.max_baseline_ratio = 54.0;
  EXPECT_FALSE(triangulate(one, one_camera, options));
}

// The random-walk covariance of three observations (stereo, stereo 10 px to the right, left-only
// 20 px further down), focal 100 px, the default noise (sd 0.3, a 0.065, b 0.01, sigma_d 0.15 px):
// C_0 = 0.09, C_1 = 0.09 + 0.065^2 + (0.01 * 10)^2 = 0.104225, C_2 = C_1 + 0.065^2 + 0.2^2 =
// 0.14845 px^2; rows x_L, y_L, x_R | x_L, y_L, x_R | x_L, y_L.
TEST(TrackNoise, RandomWalkCovarianceMatchesHandComputedValues) {
  const double f = 100.0;
  std::vector<Observation> obs(3);
  obs[0].left = {0.0, 0.0};
  obs[0].stereo = true;
  obs[1].left = {0.1, 0.0};
  obs[1].stereo = true;
  obs[2].left = {0.1, 0.2};
  RandomWalkTrackNoise noise;
  noise.step_sigma_px = 0.065;
  noise.step_flow_fraction = 0.01;
  const Eigen::MatrixXd R = track_covariance(obs, noise, f) * f * f;
  ASSERT_EQ(R.rows(), 8);
  const double C0 = 0.09, C1 = 0.104225, C2 = 0.14845, d2 = 0.0225;
  EXPECT_NEAR(R(0, 0), C0, 1e-12);
  EXPECT_NEAR(R(2, 2), C0 + d2, 1e-12);  // x_R: the left's error and the disparity's
  EXPECT_NEAR(R(0, 2), C0, 1e-12);       // x_L and x_R share the track's error
  EXPECT_NEAR(R(3, 3), C1, 1e-12);
  EXPECT_NEAR(R(5, 5), C1 + d2, 1e-12);
  EXPECT_NEAR(R(6, 6), C2, 1e-12);
  EXPECT_NEAR(R(7, 7), C2, 1e-12);
  EXPECT_NEAR(R(3, 6), C1, 1e-12);  // cov(x_1, x_2) = C_min(1,2)
  EXPECT_NEAR(R(5, 6), C1, 1e-12);
  EXPECT_NEAR(R(2, 6), C0, 1e-12);
  EXPECT_NEAR(R(1, 7), C0, 1e-12);
  EXPECT_NEAR(R(4, 7), C1, 1e-12);
  EXPECT_EQ(R(0, 1), 0.0);  // x and y independent
  EXPECT_EQ(R(1, 2), 0.0);
  EXPECT_EQ(R(4, 6), 0.0);
  EXPECT_TRUE(R.isApprox(R.transpose()));
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(R).info(), Eigen::Success);
}

// The scale-change term: a step whose depth goes from Z_(k-1) to Z_k adds (c |Z_(k-1)/Z_k - 1|)^2.
TEST(TrackNoise, ScaleChangeTermAddsToTheStepsItChanges) {
  const double f = 100.0;
  std::vector<Observation> obs(3);
  obs[1].left = {0.1, 0.0};
  obs[2].left = {0.1, 0.2};
  RandomWalkTrackNoise noise;
  noise.step_sigma_px = 0.065;
  noise.step_flow_fraction = 0.01;
  noise.step_scale_px = 4.0;
  const std::vector<double> depths = {10.0, 8.0, 8.0};  // g_1 = 0.25, g_2 = 0
  const Eigen::MatrixXd R = track_covariance(obs, noise, f, depths) * f * f;
  ASSERT_EQ(R.rows(), 6);
  // C_1 = 0.09 + 0.065^2 + (0.01 * 10)^2 + (4 * 0.25)^2; C_2 = C_1 + 0.065^2 + (0.01 * 20)^2.
  const double C1 = 0.104225 + 1.0, C2 = C1 + 0.004225 + 0.04;
  EXPECT_NEAR(R(0, 0), 0.09, 1e-12);
  EXPECT_NEAR(R(2, 2), C1, 1e-12);
  EXPECT_NEAR(R(4, 4), C2, 1e-12);
  EXPECT_NEAR(R(2, 4), C1, 1e-12);
  // Without depths the term is absent, and a depth per observation is required.
  EXPECT_NEAR((track_covariance(obs, noise, f) * f * f)(2, 2), 0.104225, 1e-12);
  EXPECT_THROW(track_covariance(obs, noise, f, std::vector<double>{1.0, 2.0}),
               std::invalid_argument);
}

/// Exact measurements of `features` known points from `clone_count` true clones; the filter
/// starts from perturbed clones with a covariance that covers the perturbation.
struct PerturbedScene {
  std::vector<Clone> truth;
  std::vector<FeatureTrack> tracks;
  VioState state;
  double baseline = 0.11, fx = 450.0;
  std::vector<const FeatureTrack*> pointers() const {
    std::vector<const FeatureTrack*> out;
    for (const auto& t : tracks) out.push_back(&t);
    return out;
  }
  /// Sum over clones of position and rotation error against the truth.
  double error() const {
    double e = 0;
    for (std::size_t i = 0; i < truth.size(); ++i)
      e += (state.clones[i].p_WI - truth[i].p_WI).norm() +
           so3_log(state.clones[i].R_WI * truth[i].R_WI.transpose()).norm();
    return e;
  }
};

PerturbedScene perturbed_scene(int clone_count, int features) {
  PerturbedScene scene;
  VioState truth;
  truth.R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera looks along body x
  truth.p_IC = {0.05, -0.02, 0.01};
  for (int i = 0; i < clone_count; ++i) {
    Clone c;
    c.t_ns = i;
    c.R_WI = so3_exp(Eigen::Vector3d(0.01 * i, -0.02 * i, 0.05 * i));
    c.p_WI = {0.2 * i, 0.03 * i, -0.01 * i};
    scene.truth.push_back(c);
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int f = 0; f < features; ++f) {
    const Eigen::Vector3d p_W(5 + 3 * uniform(rng), 2 * uniform(rng), 1.5 * uniform(rng));
    FeatureTrack track;
    track.id = f;
    for (const Clone& c : scene.truth) {
      CameraPose cam{c.R_WI * truth.R_IC, c.p_WI + c.R_WI * truth.p_IC};
      Observation o = observe(cam, p_W, scene.baseline, true);
      o.t_ns = c.t_ns;
      track.observations.push_back(o);
    }
    scene.tracks.push_back(track);
  }
  VioState& state = scene.state;
  state = truth;
  state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
  state.P.diagonal().setConstant(1e-12);
  const double s_theta = 0.005, s_pos = 0.02;
  for (std::size_t i = 0; i < scene.truth.size(); ++i) {
    state.augment_clone();
    Clone& c = state.clones.back();
    c = scene.truth[i];
    const int at = VioState::clone_index(i);
    state.P.block(at, 0, 6, state.dim()).setZero();
    state.P.block(0, at, state.dim(), 6).setZero();
    // The first clone is exact and certain: it fixes the gauge (the features only constrain
    // the clones relative to each other).
    const double st = i == 0 ? 1e-8 : s_theta, sp = i == 0 ? 1e-8 : s_pos;
    state.P.block<3, 3>(at, at) = st * st * Eigen::Matrix3d::Identity();
    state.P.block<3, 3>(at + 3, at + 3) = sp * sp * Eigen::Matrix3d::Identity();
    if (i == 0) continue;
    c.R_WI = so3_exp(Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)) * s_theta) * c.R_WI;
    c.p_WI += Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)) * s_pos;
  }
  return scene;
}

// One update must pull the perturbed clones to the truth, with the stacked H (the default: the
// paper's Eq. 1 on all the accepted features' rows, in groups of at most n rows) and with it
// compressed (as msckf_vio).
TEST(MsckfUpdater, UpdateMovesPerturbedClonesTowardTheTruth) {
  for (const bool compression : {false, true}) {
    SCOPED_TRACE(compression ? "compressed" : "stacked");
    VioOptions options;
    options.estimate_extrinsics = false;
    options.track_error_correlation = 0;  // exact, independent measurements: 1 px white noise
    options.measurement_compression = compression;
    PerturbedScene scene = perturbed_scene(6, 60);
    const double before = scene.error();
    const int n = scene.state.dim();
    MsckfUpdater updater(options, scene.baseline, scene.fx);
    KernelRecorder recorder;
    const UpdateReport report = updater.update(scene.state, scene.pointers(), recorder);
    EXPECT_GE(report.triangulated, 40);  // the perturbed clones leave a few above the RMS limit
    EXPECT_GT(report.accepted, 30);
    EXPECT_TRUE(report.updated);
    EXPECT_LT(scene.error(), 0.2 * before);
    // 2 or 3 rows per observation (mono or stereo: x_L, y_L, x_R), 3 removed per feature by the
    // null-space projection: far more rows than the 36 clone columns, compressed to those 36 or
    // not.
    EXPECT_GE(report.rows, report.accepted * (2 * 6 - 3));
    EXPECT_LE(report.rows, report.accepted * (3 * 6 - 3));
    EXPECT_GT(report.rows, 10 * 36);
    EXPECT_EQ(report.rows_used, compression ? 36 : report.rows);
    // The kernels of one update, in order; each kalman_gain's m is the height of the H it
    // uses: all the compressed rows at once, or groups of whole features of at most n rows
    // (a feature has at most 3 * 6 - 3 = 15 rows, so a group holds more than n - 15).
    std::vector<std::string> names;
    std::vector<std::int64_t> heights;
    for (const auto& k : recorder.take()) {
      names.push_back(k.kernel);
      if (k.kernel == "kalman_gain") heights.push_back(k.m);
    }
    const std::int64_t total = std::accumulate(heights.begin(), heights.end(), std::int64_t{0});
    EXPECT_EQ(total, report.rows_used);
    EXPECT_EQ(static_cast<int>(heights.size()), report.gains);
    for (std::size_t g = 0; g < heights.size(); ++g) {
      EXPECT_LE(heights[g], n);
      if (g + 1 < heights.size()) {
        EXPECT_GT(heights[g], n - 15);
      }
    }
    std::vector<std::string> expected{"triangulation", "jacobians", "nullspace_projection"};
    if (compression) expected.push_back("compression");
    if (compression) {
      EXPECT_EQ(report.gains, 1);
    } else {
      EXPECT_GE(report.gains, report.rows / n);
    }
    for (int g = 0; g < report.gains; ++g) {
      expected.push_back("kalman_gain");
      expected.push_back("covariance_update");
    }
    EXPECT_EQ(names, expected);
  }
}

// The null-space projection records what it computes, a batch per shape: per feature of R rows
// a qr R x 3 and the three products applying Qᵀ to [H_x r] (n + 1 columns); per gated feature
// an LDLᵀ of its R - 3 projected rows. The projected rows add up to the gates' rows, and the
// accepted ones (report.rows) are among them.
TEST(MsckfUpdater, NullSpaceProjectionRecordsItsOpsByShape) {
  VioOptions options;
  options.estimate_extrinsics = false;
  options.track_error_correlation = 0;
  PerturbedScene scene = perturbed_scene(6, 60);
  const std::int64_t n = scene.state.dim();
  MsckfUpdater updater(options, scene.baseline, scene.fx);
  KernelRecorder recorder;
  const UpdateReport report = updater.update(scene.state, scene.pointers(), recorder);
  const auto kernels = recorder.take();
  const auto k = std::find_if(kernels.begin(), kernels.end(),
                              [](const auto& r) { return r.kernel == "nullspace_projection"; });
  ASSERT_NE(k, kernels.end());
  std::int64_t features = 0, projected_rows = 0, gated = 0, gated_rows = 0;
  for (std::size_t i = 0; i < k->ops.size(); ++i) {
    const trace::OpRecord& op = k->ops[i];
    EXPECT_GE(op.batch, 1);
    if (op.op == trace::Op::Qr) {
      EXPECT_EQ(op.n, 3);
      ASSERT_LT(i + 3, k->ops.size());
      EXPECT_EQ(k->ops[i + 1].op, trace::Op::Gemm);
      EXPECT_EQ(k->ops[i + 1].n, n + 1);
      EXPECT_EQ(k->ops[i + 1].k, op.m);
      EXPECT_EQ(k->ops[i + 3].m, op.m);
      EXPECT_EQ(k->ops[i + 3].batch, op.batch);
      features += op.batch;
      projected_rows += (op.m - 3) * op.batch;
    }
    if (op.op == trace::Op::Ldlt) {
      gated += op.batch;
      gated_rows += op.m * op.batch;
    }
  }
  EXPECT_EQ(features, report.triangulated);  // six observations each: all are projected
  EXPECT_EQ(gated, features);
  EXPECT_EQ(gated_rows, projected_rows);
  EXPECT_EQ(k->m, report.rows);
  EXPECT_LE(k->m, projected_rows);
  EXPECT_EQ(k->k, report.accepted);
  EXPECT_LT(k->ops.size(), static_cast<std::size_t>(features));  // batched by shape
}

// The random-walk track noise (rows whitened per feature before the null-space projection)
// pulls the perturbed clones to the truth as the white model does.
TEST(MsckfUpdater, RandomWalkTrackNoiseUpdateMovesClonesTowardTheTruth) {
  VioOptions options;
  options.estimate_extrinsics = false;
  options.track_error_correlation = 0;
  options.track_noise = VioOptions::TrackNoise::kRandomWalk;
  PerturbedScene scene = perturbed_scene(6, 60);
  const double before = scene.error();
  MsckfUpdater updater(options, scene.baseline, scene.fx);
  KernelRecorder recorder;
  const UpdateReport report = updater.update(scene.state, scene.pointers(), recorder);
  EXPECT_GT(report.accepted, 30);
  EXPECT_TRUE(report.updated);
  EXPECT_LT(scene.error(), 0.2 * before);
}

// With R = sigma^2 I the stacked update of Eq. 1 has three equal forms, to round-off: one
// Kalman gain on all the rows; the default, groups of whole features of at most n rows updating
// one after the other at the same linearization point; and QR compression (H = Q1 T,
// r -> Q1^T r). Same state correction and covariance on a window of 12 clones and 80 features.
TEST(MsckfUpdater, GroupedStackedAndCompressedUpdatesAgree) {
  VioOptions grouped_options;
  grouped_options.estimate_extrinsics = false;
  grouped_options.track_error_correlation = 0;
  ASSERT_FALSE(grouped_options.measurement_compression);  // the default
  VioOptions stacked_options = grouped_options;
  stacked_options.max_gain_rows = 100000;
  VioOptions compressed_options = grouped_options;
  compressed_options.measurement_compression = true;
  const PerturbedScene scene = perturbed_scene(12, 80);
  PerturbedScene grouped = scene, stacked = scene, compressed = scene;
  KernelRecorder grouped_recorder, stacked_recorder, compressed_recorder;
  const UpdateReport g = MsckfUpdater(grouped_options, scene.baseline, scene.fx)
                             .update(grouped.state, grouped.pointers(), grouped_recorder);
  const UpdateReport a = MsckfUpdater(stacked_options, scene.baseline, scene.fx)
                             .update(stacked.state, stacked.pointers(), stacked_recorder);
  const UpdateReport c = MsckfUpdater(compressed_options, scene.baseline, scene.fx)
                             .update(compressed.state, compressed.pointers(), compressed_recorder);
  ASSERT_TRUE(g.updated);
  ASSERT_TRUE(a.updated);
  ASSERT_TRUE(c.updated);
  EXPECT_EQ(a.rows, c.rows);
  EXPECT_EQ(a.rows_used, a.rows);
  EXPECT_EQ(a.gains, 1);
  EXPECT_EQ(g.rows_used, g.rows);
  EXPECT_GT(g.gains, 3);           // 80 features of up to 33 rows, groups of <= n = 97 rows
  EXPECT_LT(c.rows_used, c.rows);  // compressed to the columns H touches
  EXPECT_LE(c.rows_used, 6 * 12);
  for (const PerturbedScene* other : {&grouped, &compressed}) {
    // State correction: the clones moved by the same amount (relative to the move).
    for (std::size_t i = 0; i < scene.truth.size(); ++i) {
      const Eigen::Vector3d move = stacked.state.clones[i].p_WI - scene.state.clones[i].p_WI;
      EXPECT_LE((stacked.state.clones[i].p_WI - other->state.clones[i].p_WI).norm(),
                1e-9 * std::max(move.norm(), 1e-3));
      EXPECT_LE(
          so3_log(stacked.state.clones[i].R_WI * other->state.clones[i].R_WI.transpose()).norm(),
          1e-9);
    }
    EXPECT_LE((stacked.state.P - other->state.P).norm(), 1e-9 * stacked.state.P.norm());
  }
  int compression_kernels = 0;
  for (const auto& k : compressed_recorder.take())
    compression_kernels += k.kernel == "compression" ? 1 : 0;
  EXPECT_EQ(compression_kernels, 1);
}

// First-estimate Jacobians in the MSCKF update: the clones' current positions differ from their
// first estimates (as after earlier updates); the covariance is large only along the 4
// unobservable directions at the first estimates (yaw about world z: dtheta_j = e_z,
// dp_j = [e_z]x p_j,fe; translation: dp_j = I). With H N = 0 after the null-space projection
// the update gains no information along them: their variance stays.
TEST(MsckfUpdater, FirstEstimateJacobiansGainNoInformationAlongTheNullSpace) {
  VioOptions options;
  options.estimate_extrinsics = false;
  const double b = 0.11, fx = 450.0;
  VioState state;
  state.R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  state.p_IC = {0.05, -0.02, 0.01};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<Clone> truth;
  for (int i = 0; i < 6; ++i) {
    Clone c;
    c.t_ns = i;
    c.R_WI = so3_exp(Eigen::Vector3d(0.01 * i, -0.02 * i, 0.05 * i));
    c.p_WI = {0.2 * i, 0.03 * i, -0.01 * i};
    truth.push_back(c);
  }
  std::vector<FeatureTrack> tracks;
  for (int f = 0; f < 40; ++f) {
    const Eigen::Vector3d p_W(5 + 3 * uniform(rng), 2 * uniform(rng), 1.5 * uniform(rng));
    FeatureTrack track;
    track.id = f;
    for (const Clone& c : truth) {
      Observation o = observe({c.R_WI * state.R_IC, c.p_WI + c.R_WI * state.p_IC}, p_W, b, true);
      o.t_ns = c.t_ns;
      track.observations.push_back(o);
    }
    tracks.push_back(track);
  }
  state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
  for (const Clone& c : truth) {
    state.augment_clone();
    Clone& e = state.clones.back();
    e = c;
    e.p_fe = c.p_WI + 0.03 * Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
    e.has_fe = true;
  }
  const int n = state.dim();
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, 4);
  for (std::size_t i = 0; i < state.clones.size(); ++i) {
    const int at = VioState::clone_index(i);
    N(at + 2, 0) = 1;
    N.block<3, 1>(at + 3, 0) = Eigen::Vector3d::UnitZ().cross(state.clones[i].p_fe);
    N.block<3, 3>(at + 3, 1).setIdentity();
  }
  const double eps = 1e-8;
  state.P = N * N.transpose() + eps * Eigen::MatrixXd::Identity(n, n);
  state.P.topLeftCorner(kCoreDim, kCoreDim) = eps * Eigen::MatrixXd::Identity(kCoreDim, kCoreDim);
  const Eigen::MatrixXd before = N.transpose() * state.P * N;
  MsckfUpdater updater(options, b, fx);
  std::vector<const FeatureTrack*> pointers;
  for (const auto& t : tracks) pointers.push_back(&t);
  KernelRecorder recorder;
  ASSERT_TRUE(updater.update(state, pointers, recorder).updated);
  const Eigen::MatrixXd after = N.transpose() * state.P * N;
  // Without FEJ (p_WI in [d]x) the yaw variance drops by orders of magnitude here.
  EXPECT_LT((after - before).norm(), 1e-3 * before.norm());
}

// GPS fusion: the first fixes align the frames, the later ones correct a position error.
// The moving initializer on a noise-free stereo rig (camera = body): the body turns at a constant
// rate while accelerating; the gyro reads the rate plus a bias of 0.08 rad/s (as EuRoC V1_01's
// ADIS16448 about z). The bias comes out of the visual rotations (VINS-Mono's gyroscope bias
// calibration) to 1e-3 rad/s, and with it the tilt and the velocity.
TEST(Initializer, MovingStartCalibratesTheGyroBiasFromTheVisualRotations) {
  for (const Eigen::Vector3d& true_bias :
       {Eigen::Vector3d(0.01, -0.02, 0.08), Eigen::Vector3d(0, 0, 0)}) {
    SCOPED_TRACE(true_bias.transpose());
    const double g = 9.81, focal = 450.0, baseline = 0.11;
    const Eigen::Vector3d omega(0.05, -0.3, 0.1);  // body rates, rad/s
    // Camera (= body) looking along world x, its y axis down.
    Eigen::Matrix3d R0;
    R0.col(0) = -Eigen::Vector3d::UnitY();
    R0.col(1) = -Eigen::Vector3d::UnitZ();
    R0.col(2) = Eigen::Vector3d::UnitX();
    const auto rotation = [&](double t) { return Eigen::Matrix3d(R0 * so3_exp(omega * t)); };
    const auto position = [](double t) {
      return Eigen::Vector3d(1.0 * t, 0.2 * std::sin(2 * t), 0.1 * t * t);
    };
    const auto velocity = [](double t) {
      return Eigen::Vector3d(1.0, 0.4 * std::cos(2 * t), 0.2 * t);
    };
    const auto acceleration = [](double t) {
      return Eigen::Vector3d(0.0, -0.8 * std::sin(2 * t), 0.2);
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < 200; ++i) points.emplace_back(8 + 4 * u(rng), 4 * u(rng), 2 * u(rng));
    VioOptions options;
    Initializer initializer(options, Eigen::Isometry3d::Identity(), focal);
    const std::int64_t frame_ns = 50'000'000, imu_ns = 5'000'000;
    std::int64_t imu_t = 0;
    std::optional<InitialState> state;
    for (int k = 0; k < options.init_frames && !state; ++k) {
      const std::int64_t t_ns = k * frame_ns;
      std::vector<datasets::ImuSample> imu;
      for (; imu_t <= t_ns; imu_t += imu_ns) {
        const double t = static_cast<double>(imu_t) * 1e-9;
        imu.push_back({imu_t, omega + true_bias,
                       rotation(t).transpose() * (acceleration(t) + Eigen::Vector3d(0, 0, g))});
      }
      const double t = static_cast<double>(t_ns) * 1e-9;
      std::vector<FrameFeature> features;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Eigen::Vector3d p_C = rotation(t).transpose() * (points[i] - position(t));
        if (p_C.z() < 1.0) continue;
        Observation o{t_ns, p_C.head<2>() / p_C.z(), true, (p_C.x() - baseline) / p_C.z()};
        features.push_back({static_cast<std::int64_t>(i), o, p_C.z()});
      }
      state = initializer.add_frame(t_ns, imu, std::move(features));
    }
    ASSERT_TRUE(state.has_value()) << initializer.last_reason();
    EXPECT_FALSE(state->static_start);
    EXPECT_LT((state->gyro_bias - true_bias).norm(), 1e-3) << state->gyro_bias.transpose();
    const double t_end = static_cast<double>(state->t_ns) * 1e-9;
    // Tilt: the body's "up" agrees (yaw is the initializer's choice).
    const Eigen::Vector3d up_true = rotation(t_end).transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up = state->R_WI.transpose() * Eigen::Vector3d::UnitZ();
    EXPECT_LT(std::acos(std::min(1.0, up.dot(up_true))), 2e-3);
    // Velocity: its vertical part and its length (yaw-free).
    EXPECT_NEAR(state->v_WI.z(), velocity(t_end).z(), 0.02);
    EXPECT_NEAR(state->v_WI.norm(), velocity(t_end).norm(), 0.02);
  }
}

TEST(GpsFusion, AlignsThenCorrectsDrift) {
  VioOptions options;
  options.gps_align_min_extent_m = 10.0;
  GpsFusion fusion(options);
  VioState state;
  state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
  state.P.diagonal().head(kImuDim).setConstant(1e-4);
  state.v_WI = {10, 0, 0};
  // GPS frame: the filter frame turned by 30 degrees and shifted.
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d shift(100, -50, 3);
  KernelRecorder recorder;
  EXPECT_EQ(fusion.process(state, {}, recorder).fixes, 0);
  EXPECT_TRUE(recorder.take().empty());  // no fixes, no kernel
  for (int k = 0; k < 20; ++k) {
    state.t_ns = k * 100'000'000;
    state.p_WI = {1.0 * k, 0, 0};
    datasets::GpsFix fix{state.t_ns, Rz * state.p_WI + shift, 0.1};
    fusion.process(state, std::span(&fix, 1), recorder);
  }
  ASSERT_TRUE(fusion.aligned());
  EXPECT_NEAR(state.yaw_GV, 0.5236, 1e-6);
  EXPECT_LT((state.t_GV - shift).norm(), 1e-6);
  // The filter now believes it is 0.5 m off to the side; the fixes pull it back.
  state.P.block<3, 3>(kPos, kPos) = 0.25 * Eigen::Matrix3d::Identity();
  state.t_ns = 2'000'000'000;
  const Eigen::Vector3d true_position(20, 0, 0);
  state.p_WI = true_position + Eigen::Vector3d(0, 0.5, 0);
  for (int k = 0; k < 5; ++k) {
    datasets::GpsFix fix{state.t_ns, Rz * true_position + shift, 0.1};
    const GpsReport report = fusion.process(state, std::span(&fix, 1), recorder);
    EXPECT_EQ(report.fused, 1);
  }
  EXPECT_LT((state.p_WI - true_position).norm(), 0.1);
  const auto kernels = recorder.take();
  ASSERT_FALSE(kernels.empty());
  EXPECT_EQ(kernels.back().kernel, "gps_fusion");
}

// The fixes' height is fused only with gps_fuse_vertical (default on); without it they correct
// the horizontal position and leave the VIO's height alone.
TEST(GpsFusion, HeightOnlyWhenVertical) {
  for (const bool vertical : {false, true}) {
    VioOptions options;
    options.gps_align_min_extent_m = 10.0;
    options.gps_fuse_vertical = vertical;
    GpsFusion fusion(options);
    VioState state;
    state.P = Eigen::MatrixXd::Zero(kCoreDim, kCoreDim);
    state.P.diagonal().head(kImuDim).setConstant(1e-4);
    state.v_WI = {10, 0, 0};
    KernelRecorder recorder;
    for (int k = 0; k < 20; ++k) {
      state.t_ns = k * 100'000'000;
      state.p_WI = {1.0 * k, 0, 0};
      datasets::GpsFix fix{state.t_ns, state.p_WI, 0.1};
      fusion.process(state, std::span(&fix, 1), recorder);
    }
    ASSERT_TRUE(fusion.aligned());
    state.P.block<3, 3>(kPos, kPos) = 0.25 * Eigen::Matrix3d::Identity();
    state.t_ns = 2'000'000'000;
    const Eigen::Vector3d true_position(20, 0, 0);
    state.p_WI = true_position + Eigen::Vector3d(0, 0.5, 0.5);
    for (int k = 0; k < 5; ++k) {
      datasets::GpsFix fix{state.t_ns, true_position, 0.1};
      EXPECT_EQ(fusion.process(state, std::span(&fix, 1), recorder).fused, 1);
    }
    EXPECT_LT(std::abs(state.p_WI.y()), 0.1) << vertical;
    if (vertical) {
      EXPECT_LT(std::abs(state.p_WI.z()), 0.1);
    } else {
      EXPECT_DOUBLE_EQ(state.p_WI.z(), 0.5);
      EXPECT_DOUBLE_EQ(state.P(kPos + 2, kPos + 2), 0.25);
    }
  }
}

}  // namespace
}  // namespace edx::backend::vio

namespace edx::backend::vio::testing {
namespace {

// The diagnostics' settings ($EDX_VIO_FIRST_WINDOW_CHECK, $EDX_VIO_MAX_TRACK_AGE): a number at
// least the minimum, or a one-line error naming the variable.
TEST(DiagnosticSettings, EnvNumberParsesOrNamesTheVariable) {
  const char* name = "EDX_VIO_TEST_SETTING";
  ::setenv(name, "1.5", 1);
  EXPECT_DOUBLE_EQ(env_number(name, 0), 1.5);
  for (const char* bad : {"", "abc", "1.5px", "-2"}) {
    ::setenv(name, bad, 1);
    try {
      env_number(name, 0);
      ADD_FAILURE() << "expected a throw for '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("$EDX_VIO_TEST_SETTING"), std::string::npos) << message;
      EXPECT_NE(message.find(std::string("'") + bad + "'"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  ::unsetenv(name);
  EXPECT_THROW(env_number(name, 0), std::invalid_argument);
}

}  // namespace
}  // namespace edx::backend::vio::testing
