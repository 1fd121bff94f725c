#include "workloads/backend/slam/slam_backend.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "workloads/backend/slam/keyframe_selector.hpp"
#include "workloads/backend/slam/lm_solver.hpp"
#include "workloads/backend/slam/marginalizer.hpp"
#include "workloads/backend/slam/tracker.hpp"

namespace edx::backend::slam {
namespace {

/// Gravity-aligned orientation from the mean specific force f (body frame, at rest or slow):
/// f ~ R_wb^T (0, 0, |g|), so R_wb rotates f onto +z (yaw left at that of the minimal rotation).
Eigen::Matrix3d gravity_aligned(std::span<const datasets::ImuSample> samples) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const datasets::ImuSample& s : samples) f += s.accel_m_s2;
  if (samples.empty() || f.norm() < 1e-6) return Eigen::Matrix3d::Identity();
  return Eigen::Quaterniond::FromTwoVectors(f.normalized(), Eigen::Vector3d::UnitZ())
      .toRotationMatrix();
}

}  // namespace

SlamBackend::SlamBackend(const BackendCamera& camera, std::optional<ImuNoiseDensities> imu,
                         const SlamOptions& options, std::string source)
    : options_(options), imu_(options.use_imu ? imu : std::nullopt), source_(std::move(source)) {
  options_.validate();
  if (!(camera.fx > 0) || !(camera.fy > 0) || !(camera.baseline_m > 0)) {
    throw std::runtime_error(fmt::format(
        "slam backend: camera fx, fy and baseline must be > 0 (got fx={} fy={} baseline={})",
        camera.fx, camera.fy, camera.baseline_m));
  }
  window_.camera = camera;
  window_.state_dim = imu_ ? 15 : 6;
}

void SlamBackend::integrate_imu(const BackendInput& input) {
  if (!imu_) return;
  auto k = recorder_.kernel("preintegration");
  k.record().m = static_cast<std::int64_t>(input.imu.size());
  if (!initialized_) {
    // The reading in force at the first frame: the last one at or before it.
    for (const datasets::ImuSample& s : input.imu) {
      if (s.t_ns <= input.t_ns) imu_sample_ = s;
    }
    imu_t_ns_ = input.t_ns;
    return;
  }
  if (imu_since_keyframe_) {
    integrate_interval(*imu_since_keyframe_, imu_t_ns_, imu_sample_, input.imu, input.t_ns);
  }
}

Eigen::Isometry3d SlamBackend::predict_pose() const {
  Eigen::Isometry3d T = last_pose_;
  if (previous_pose_) T = last_pose_ * (previous_pose_->inverse() * last_pose_);
  if (imu_ && imu_since_keyframe_ && !window_.keyframes.empty()) {
    const KeyframeState& kf = window_.keyframes.back();
    T.linear() = kf.R * imu_since_keyframe_->corrected_delta_R(kf.bg);
  }
  return T;
}

void SlamBackend::add_keyframe(const BackendInput& input, const Eigen::Isometry3d& T_world_body,
                               const std::vector<std::int64_t>* inlier_tracks) {
  KeyframeState kf;
  kf.id = next_keyframe_id_++;
  kf.t_ns = input.t_ns;
  kf.frame_index = input.frontend->index;
  kf.R = T_world_body.linear();
  kf.p = T_world_body.translation();
  kf.features = input.frontend->features;
  if (imu_ && !window_.keyframes.empty()) {
    const KeyframeState& last = window_.keyframes.back();
    const double dt = static_cast<double>(kf.t_ns - last.t_ns) * 1e-9;
    kf.v = dt > 0 ? Eigen::Vector3d((kf.p - last.p) / dt) : last.v;
    kf.ba = last.ba;
    kf.bg = last.bg;
    kf.imu_from_previous = std::move(imu_since_keyframe_);
  }
  window_.keyframes.push_back(std::move(kf));
  ++statistics_.keyframes;

  // Observations of existing landmarks, and new landmarks from stereo features.
  auto k = recorder_.kernel("triangulation");
  const KeyframeState& added = window_.keyframes.back();
  int created = 0, observed = 0;
  // Stereo depth with the current disparity offset: z = fx b / (d + delta).
  const double fb = window_.camera.fx * window_.camera.baseline_m;
  auto stereo_depth = [&](const frontend::Feature& f) {
    const double disparity = f.disparity + window_.disparity_offset_px;
    return disparity > 0 ? fb / disparity : 0.0;
  };
  for (const frontend::Feature& f : added.features) {
    Observation o;
    o.keyframe_id = added.id;
    o.left = {f.left.x, f.left.y};
    const auto it = window_.landmarks.find(f.id);
    // The right image only for points close enough (stereo_max_depth_baselines), judged on the
    // landmark's depth where it exists, else on this stereo depth.
    const double depth =
        it != window_.landmarks.end() ? 1.0 / it->second.inverse_depth : stereo_depth(f);
    if (f.stereo && is_close(depth)) o.right = Eigen::Vector2d(f.right.x, f.right.y);
    if (it != window_.landmarks.end()) {
      if (inlier_tracks != nullptr &&
          !std::binary_search(inlier_tracks->begin(), inlier_tracks->end(), f.id)) {
        continue;  // a track tracking rejected: neither observed nor a new landmark
      }
      it->second.observations.push_back(o);
      ++observed;
      continue;
    }
    if (!f.stereo || created >= options_.max_new_landmarks_per_keyframe) continue;
    const double z = stereo_depth(f);
    if (z < options_.min_landmark_depth_m || z > options_.max_landmark_depth_m) continue;
    const BackendCamera& cam = window_.camera;
    Landmark l;
    l.track_id = f.id;
    l.map_id = next_landmark_id_++;
    l.anchor_id = added.id;
    l.bearing = {(f.left.x - cam.cx) / cam.fx, (f.left.y - cam.cy) / cam.fy, 1.0};
    l.inverse_depth = 1.0 / z;
    l.descriptor = f.descriptor;
    l.observations.push_back(o);
    window_.landmarks.emplace(f.id, std::move(l));
    ++created;
  }
  statistics_.landmarks_created += created;
  k.record().m = created;
  k.record().n = observed;
}

bool SlamBackend::is_close(double depth_m) const {
  return options_.stereo_max_depth_baselines <= 0 ||
         depth_m < options_.stereo_max_depth_baselines * window_.camera.baseline_m;
}

void SlamBackend::initialize(const BackendInput& input) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (imu_) T.linear() = gravity_aligned(input.imu);
  add_keyframe(input, T);
  // Gauge prior on the first keyframe: position and yaw (and without an IMU, roll and pitch)
  // fixed; with an IMU, loose roll/pitch and bias priors. Rotation rows in world axes:
  // r_theta = Sigma^-1/2 R0 theta.
  const int d = window_.state_dim;
  const KeyframeState& kf0 = window_.keyframes.front();
  Prior prior;
  prior.keyframe_ids = {kf0.id};
  prior.linearization_points = {kf0.navigation_state()};
  prior.J = Eigen::MatrixXd::Zero(d, d);
  prior.r0 = Eigen::VectorXd::Zero(d);
  constexpr double kFixed = 1e-4;
  const double tilt = imu_ ? options_.initial_tilt_sigma_rad : kFixed;
  prior.J.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity() / kFixed;
  prior.J.block<3, 3>(3, 3) = Eigen::Vector3d(1 / tilt, 1 / tilt, 1 / kFixed).asDiagonal() * kf0.R;
  if (d == 15) {
    prior.J.block<3, 3>(9, 9) = Eigen::Matrix3d::Identity() / options_.initial_accel_bias_sigma;
    prior.J.block<3, 3>(12, 12) = Eigen::Matrix3d::Identity() / options_.initial_gyro_bias_sigma;
  }
  window_.prior = std::move(prior);
  if (imu_) imu_since_keyframe_.emplace(kf0.ba, kf0.bg, *imu_);
  last_pose_ = T;
  initialized_ = true;
}

void SlamBackend::map_window() {
  const LmReport lm = optimize_window(window_, options_, recorder_);
  statistics_.lm_iterations += lm.iterations;
  statistics_.disparity_offset_px = window_.disparity_offset_px;
  {
    auto k = recorder_.kernel("outlier_rejection");
    statistics_.outliers_rejected += reject_outliers(window_, options_);
  }
  if (static_cast<int>(window_.keyframes.size()) > options_.window_size) {
    const MarginalizationReport report = marginalize_oldest(window_, options_, recorder_);
    ++statistics_.marginalizations;
    archive(report.removed, report.removed_landmarks, report.removed_positions, archive_);
  }
  if (imu_) {
    // Re-integrate the window's IMU intervals whose bias estimate moved away from the one they
    // were integrated with (the first-order bias correction is only good near it).
    auto k = recorder_.kernel("preintegration");
    for (std::size_t i = 1; i < window_.keyframes.size(); ++i) {
      KeyframeState& kf = window_.keyframes[i];
      const KeyframeState& start = window_.keyframes[i - 1];
      if (!kf.imu_from_previous) continue;
      if ((start.ba - kf.imu_from_previous->accel_bias()).norm() > 0.05 ||
          (start.bg - kf.imu_from_previous->gyro_bias()).norm() > 0.005) {
        kf.imu_from_previous->repropagate(start.ba, start.bg);
      }
    }
    const KeyframeState& last = window_.keyframes.back();
    imu_since_keyframe_.emplace(last.ba, last.bg, *imu_);
  }
}

BackendOutput SlamBackend::process(const BackendInput& input) {
  if (input.frontend == nullptr) {
    throw std::runtime_error("slam backend: frame without frontend features");
  }
  BackendOutput out;
  ++statistics_.frames;
  integrate_imu(input);
  if (!initialized_) {
    initialize(input);
    out.T_world_body = last_pose_;
    out.kernels = recorder_.take();
    return out;
  }
  const std::vector<frontend::Feature>& features = input.frontend->features;
  const Eigen::Isometry3d predicted = predict_pose();
  TrackingResult tracked;
  {
    auto k = recorder_.kernel("tracking");
    tracked = track_frame(window_, features, predicted, options_);
    k.record().m = tracked.matches;
    k.record().n = 6;
  }
  if (!tracked.ok) {
    ++statistics_.tracking_failures;
    out.status = fmt::format("tracking failed: {} of {} matches within {} px", tracked.inliers,
                             tracked.matches, options_.outlier_px);
  }
  KeyframeDecision decision;
  {
    auto k = recorder_.kernel("keyframe_selection");
    decision = select_keyframe(window_, features, input.t_ns, options_);
    k.record().m = decision.shared_tracks;
  }
  Eigen::Isometry3d pose = tracked.T_world_body;
  if (decision.is_keyframe || !tracked.ok) {
    std::sort(tracked.inlier_tracks.begin(), tracked.inlier_tracks.end());
    add_keyframe(input, pose, tracked.ok ? &tracked.inlier_tracks : nullptr);
    map_window();
    pose = window_.keyframes.back().T_world_body();
  }
  previous_pose_ = last_pose_;
  last_pose_ = pose;
  out.T_world_body = pose;
  out.kernels = recorder_.take();
  return out;
}

MapKeyframe SlamBackend::to_map_keyframe(const KeyframeState& keyframe) const {
  MapKeyframe kf;
  kf.id = keyframe.id;
  kf.t_ns = keyframe.t_ns;
  kf.frame_index = keyframe.frame_index;
  kf.T_world_body = keyframe.T_world_body();
  for (const frontend::Feature& f : keyframe.features) {
    MapKeypoint k;
    k.track_id = f.id;
    k.left = {f.left.x, f.left.y};
    if (f.stereo) k.right = Eigen::Vector2d(f.right.x, f.right.y);
    k.depth_m = f.stereo ? f.depth_m : 0.0;
    k.octave = f.octave;
    k.angle_deg = f.angle;
    k.descriptor = f.descriptor;
    kf.keypoints.push_back(k);
  }
  return kf;
}

void SlamBackend::archive(const KeyframeState& keyframe, const std::vector<Landmark>& landmarks,
                          const std::vector<Eigen::Vector3d>& positions, Map& map) const {
  map.keyframes.push_back(to_map_keyframe(keyframe));
  // Keypoint index of a track id in a keyframe (the removed one or one still in the window).
  auto keypoint_index = [&](std::int64_t keyframe_id,
                            std::int64_t track_id) -> std::optional<std::size_t> {
    const KeyframeState* kf = &keyframe;
    if (keyframe_id != keyframe.id) {
      const int slot = window_.slot(keyframe_id);
      if (slot < 0) return std::nullopt;
      kf = &window_.keyframes[static_cast<std::size_t>(slot)];
    }
    for (std::size_t i = 0; i < kf->features.size(); ++i) {
      if (kf->features[i].id == track_id) return i;
    }
    return std::nullopt;
  };
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const Landmark& l = landmarks[i];
    MapLandmark m;
    m.id = l.map_id;
    m.track_id = l.track_id;
    m.position = positions[i];
    m.descriptor = l.descriptor;
    for (const Observation& o : l.observations) {
      if (!o.inlier) continue;
      if (const auto index = keypoint_index(o.keyframe_id, l.track_id)) {
        m.observations.push_back({o.keyframe_id, *index});
      }
    }
    if (!m.observations.empty()) map.landmarks.push_back(std::move(m));
  }
}

Map SlamBackend::map() const {
  Map map = archive_;
  map.source = source_;
  map.camera = window_.camera;
  // The window's keyframes, oldest first, each with the landmarks anchored in it.
  for (const KeyframeState& kf : window_.keyframes) {
    std::vector<Landmark> landmarks;
    std::vector<Eigen::Vector3d> positions;
    for (const auto& [id, l] : window_.landmarks) {
      if (l.anchor_id != kf.id || !(l.inverse_depth > 0)) continue;
      landmarks.push_back(l);
      positions.push_back(window_.landmark_world(l));
    }
    archive(kf, landmarks, positions, map);
  }
  std::sort(map.landmarks.begin(), map.landmarks.end(),
            [](const MapLandmark& a, const MapLandmark& b) { return a.id < b.id; });
  return map;
}

std::unique_ptr<Backend> make_slam_backend(const datasets::Dataset& dataset,
                                           const SlamOptions& options) {
  std::optional<ImuNoiseDensities> imu;
  if (const auto noise = dataset.imu_noise(); noise && !dataset.imu().empty()) {
    imu = ImuNoiseDensities::from(*noise);
  }
  return std::make_unique<SlamBackend>(BackendCamera::from(dataset.calibration()), imu, options,
                                       dataset.name());
}

}  // namespace edx::backend::slam
