#include "workloads/backend/vio/vio_backend.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

namespace edx::backend::vio {
namespace {

const BackendCamera& checked(const BackendCamera& camera) {
  if (!(camera.fx > 0 && camera.fy > 0 && camera.baseline_m > 0)) {
    throw std::runtime_error(fmt::format(
        "vio backend: camera needs fx, fy and baseline > 0 (got fx={}, fy={}, baseline={})",
        camera.fx, camera.fy, camera.baseline_m));
  }
  return camera;
}

const VioOptions& validated(const VioOptions& options) {
  options.validate();
  return options;
}

}  // namespace

VioBackend::VioBackend(const BackendCamera& camera, const datasets::ImuNoise& imu_noise,
                       const VioOptions& options)
    : camera_(checked(camera)),
      options_(validated(options)),
      propagator_(ImuNoiseDensities::from(imu_noise, options.imu_noise_scale),
                  options.gravity_m_s2),
      initializer_(options, camera.T_body_left, camera.fx),
      updater_(options, camera.baseline_m, camera.fx),
      gps_(options),
      bias_priors_(bias_priors(options, imu_noise)) {
  if (!(imu_noise.gyro_noise_density > 0 && imu_noise.accel_noise_density > 0 &&
        imu_noise.gyro_random_walk > 0 && imu_noise.accel_random_walk > 0)) {
    throw std::runtime_error("vio backend: IMU noise densities and random walks must be > 0");
  }
}

VioBackend::BiasPriors VioBackend::bias_priors(const VioOptions& options,
                                               const datasets::ImuNoise& imu_noise) {
  return {options.init_gyro_bias_sigma.value_or(
              imu_noise.gyro_bias_sigma.value_or(VioOptions::kFallbackGyroBiasSigma)),
          options.init_accel_bias_sigma.value_or(
              imu_noise.accel_bias_sigma.value_or(VioOptions::kFallbackAccelBiasSigma))};
}

std::vector<FrameFeature> VioBackend::to_frame_features(
    const frontend::FrontendFrame& frame) const {
  std::vector<FrameFeature> out;
  out.reserve(frame.features.size());
  for (const frontend::Feature& f : frame.features) {
    FrameFeature ff;
    ff.id = f.id;
    ff.observation.left = {(f.left.x - camera_.cx) / camera_.fx,
                           (f.left.y - camera_.cy) / camera_.fy};
    if (f.stereo && f.disparity > 0) {
      ff.observation.stereo = true;
      ff.observation.right_x = (f.right.x - camera_.cx) / camera_.fx;
      ff.depth_m = f.depth_m;
    }
    out.push_back(ff);
  }
  return out;
}

/// The first-window alignment's stopping rule: at most this many Gauss-Newton updates, or an
/// update that moves no window corner by more than this (px).
constexpr int kCheckIterations = 30;
constexpr double kCheckEpsilonPx = 0.01;

void VioBackend::check_first_windows(const frontend::FrontendFrame& frame,
                                     const cv::Mat& left_image,
                                     std::vector<FrameFeature>& features) {
  auto kernel = recorder_.kernel("track_check");
  const cv::Mat prepared = frontend::FirstWindow::prepare(left_image);
  std::int64_t checked = 0, created = 0, ended = 0, iterations = 0;
  std::set<std::int64_t> ending, present;
  for (const frontend::Feature& f : frame.features) {
    present.insert(f.id);
    if (ended_by_check_.contains(f.id)) {
      ending.insert(f.id);
      continue;
    }
    const auto checked_track = first_windows_.find(f.id);
    if (checked_track == first_windows_.end()) {
      first_windows_.emplace(
          f.id, CheckedTrack{frontend::FirstWindow(prepared, f.left, options_.first_window_half_px),
                             std::nullopt, f.left});
      ++created;
      continue;
    }
    ++checked;
    // Drift = |c* - x_k|, c* where the first window's centre lands (30 updates, 0.01 px), warm
    // started from the last frame's warp moved by the track's own motion.
    CheckedTrack& track = checked_track->second;
    // Every update computed counts as work, a failed warm start's too.
    std::optional<frontend::WindowAlignment> aligned;
    int updates = 0;
    if (track.last) {
      frontend::WindowAlignment start = *track.last;
      start.centre += f.left - track.last_position;
      aligned = track.window.refine(prepared, start, kCheckIterations, kCheckEpsilonPx, &updates);
      iterations += updates;
    }
    if (!aligned) {
      aligned = track.window.align(prepared, f.left, kCheckIterations, kCheckEpsilonPx, &updates);
      iterations += updates;
    }
    if (!aligned || std::hypot(aligned->centre.x - f.left.x, aligned->centre.y - f.left.y) >
                        options_.first_window_check_px) {
      ended_by_check_.insert(f.id);
      first_windows_.erase(checked_track);
      ending.insert(f.id);
      ++ended;
      continue;
    }
    track.last = aligned;
    track.last_position = f.left;
  }
  // Tracks the frontend ended are forgotten (it never reuses an id).
  std::erase_if(first_windows_, [&](const auto& entry) { return !present.contains(entry.first); });
  std::erase_if(ended_by_check_, [&](std::int64_t id) { return !present.contains(id); });
  std::erase_if(features, [&](const FrameFeature& f) { return ending.contains(f.id); });
  kernel.record().m = checked;
  kernel.record().n = created;
  kernel.record().detail_json = nlohmann::json{{"iterations", iterations}, {"ended", ended}}.dump();
}

void VioBackend::start(const InitialState& initial) {
  state_ = VioState{};
  state_.t_ns = initial.t_ns;
  state_.R_WI = initial.R_WI;
  state_.p_WI = initial.p_WI;
  state_.v_WI = initial.v_WI;
  state_.gyro_bias = initial.gyro_bias;
  state_.R_IC = camera_.T_body_left.linear();
  state_.p_IC = camera_.T_body_left.translation();
  // Prior: roll and pitch uncertain, yaw and position define the frame (zero), velocity and
  // biases from the options, extrinsics from their calibration sigmas.
  Eigen::VectorXd sd = Eigen::VectorXd::Zero(kCoreDim);
  const double tilt = options_.init_tilt_sigma_rad;
  sd.segment<3>(kTheta) << tilt, tilt, 1e-6;
  sd.segment<3>(kPos).setConstant(1e-6);
  sd.segment<3>(kVel).setConstant(initial.static_start ? 0.01 : options_.init_velocity_sigma_m_s);
  sd.segment<3>(kGyroBias).setConstant(bias_priors_.gyro);
  sd.segment<3>(kAccelBias).setConstant(bias_priors_.accel);
  sd.segment<3>(kExtTheta).setConstant(
      options_.estimate_extrinsics ? options_.extrinsic_rotation_sigma_rad : 0.0);
  sd.segment<3>(kExtPos).setConstant(
      options_.estimate_extrinsics ? options_.extrinsic_translation_sigma_m : 0.0);
  state_.P = sd.cwiseAbs2().asDiagonal();
  // Roll/pitch are about world x and y in the left-perturbation error; the prior above is in
  // that frame already.
  tracks_.clear();
  initialized_ = true;
}

BackendOutput VioBackend::process(const BackendInput& input) {
  if (input.frontend == nullptr) throw std::runtime_error("vio backend: frontend frame missing");
  BackendOutput out;
  propagator_.add(input.imu);
  std::vector<FrameFeature> features = to_frame_features(*input.frontend);
  if (options_.first_window_check_px > 0 && input.left_image != nullptr) {
    check_first_windows(*input.frontend, *input.left_image, features);
  }
  last_update_ = {};
  last_gps_ = {};

  if (!initialized_) {
    std::optional<InitialState> initial;
    {
      auto kernel = recorder_.kernel("initialization");
      kernel.record().m = static_cast<std::int64_t>(features.size());
      initial = initializer_.add_frame(input.t_ns, input.imu, features);
    }
    if (!initial) {
      out.status = "initializing: " + initializer_.last_reason();
      out.kernels = recorder_.take();
      return out;
    }
    start(*initial);
    auto kernel = recorder_.kernel("cloning");
    state_.augment_clone();
    kernel.record().n = state_.dim();
  } else {
    ImuInterval interval;
    {
      auto kernel = recorder_.kernel("imu_propagation");
      interval = propagator_.integrate(state_, input.t_ns);
      kernel.record().m = interval.steps();
      kernel.record().n = state_.dim();
    }
    {
      auto kernel = recorder_.kernel("covariance_propagation");
      propagator_.propagate_covariance(state_, interval, &recorder_);
      kernel.record().m = interval.steps();
      kernel.record().n = state_.dim();
    }
    auto kernel = recorder_.kernel("cloning");
    state_.augment_clone();
    kernel.record().n = state_.dim();
  }

  // New observations; tracks absent from this frame have ended.
  std::set<std::int64_t> seen;
  for (const FrameFeature& f : features) {
    seen.insert(f.id);
    FeatureTrack& track = tracks_[f.id];
    track.id = f.id;
    Observation obs = f.observation;
    obs.t_ns = input.t_ns;
    track.observations.push_back(obs);
  }
  std::vector<const FeatureTrack*> used;
  std::vector<std::int64_t> used_ids;
  for (const auto& [id, track] : tracks_) {
    if (!seen.contains(id)) {
      used.push_back(&track);
      used_ids.push_back(id);
    }
  }
  const bool window_full = static_cast<int>(state_.clones.size()) > options_.max_clones;
  const std::int64_t oldest = state_.clones.front().t_ns;
  for (const auto& [id, track] : tracks_) {
    if (!seen.contains(id)) continue;
    const int length = static_cast<int>(track.observations.size());
    const bool spans_window = window_full && track.observations.front().t_ns == oldest;
    if (length >= options_.update_track_length ||
        (spans_window && length >= options_.min_track_length)) {
      used.push_back(&track);
      used_ids.push_back(id);
    }
  }
  last_update_ = updater_.update(state_, used, recorder_);
  for (std::int64_t id : used_ids) tracks_.erase(id);

  if (window_full) {
    auto kernel = recorder_.kernel("clone_marginalization");
    state_.marginalize_clone(0);
    for (auto& [id, track] : tracks_) {
      std::erase_if(track.observations, [&](const Observation& o) { return o.t_ns == oldest; });
    }
    std::erase_if(tracks_, [](const auto& entry) { return entry.second.observations.empty(); });
    kernel.record().m = kCloneDim;
    kernel.record().n = state_.dim();
  }

  last_gps_ = gps_.process(state_, input.gps, recorder_);

  out.T_world_body = state_.T_world_body();
  out.status = last_update_.updated || last_update_.tracks == 0 ? "ok" : "ok (no visual update)";
  out.kernels = recorder_.take();
  return out;
}

std::unique_ptr<Backend> make_vio_backend(const datasets::Dataset& dataset,
                                          const VioOptions& options) {
  if (dataset.imu().empty()) {
    throw std::runtime_error(
        fmt::format("{}: the vio backend needs IMU samples (imu0), found none", dataset.name()));
  }
  const datasets::ImuNoise noise =
      dataset.imu_noise().value_or(datasets::ImuNoise{.gyro_noise_density = 1.6968e-4,
                                                      .gyro_random_walk = 1.9393e-5,
                                                      .accel_noise_density = 2.0e-3,
                                                      .accel_random_walk = 3.0e-3,
                                                      .rate_hz = 200.0,
                                                      .gyro_bias_sigma = std::nullopt,
                                                      .accel_bias_sigma = std::nullopt});
  return std::make_unique<VioBackend>(BackendCamera::from(dataset.calibration()), noise, options);
}

}  // namespace edx::backend::vio
