// Frontend quality against the synthetic world's exact geometry: stereo disparities and LK
// tracks compared with ray-cast truth, on short sequences rendered in memory by edx_synthetic
// (the same renderer, rigs and trajectories `edx gen` uses).
//
// Truth. A left feature at pixel (u, v) of frame k sees the first surface hit by the ray
// through that pixel centre, d_cam = ((u - cx) / fx, (v - cy) / fy, 1), from the left camera
// T_world_left = T_world_body(t_k) * T_body_left. With the hit at depth z (camera z axis):
//   true disparity = fx * baseline / z;
// the hit point X projects into frame k + 1 at K * (T_world_left(t_{k+1})^-1 * X), the true
// position of the tracked feature.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <optional>

#include "workloads/datasets/synthetic/generator.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"
#include "workloads/datasets/synthetic/stereo_camera.hpp"
#include "workloads/datasets/synthetic/trajectory.hpp"
#include "workloads/frontend/stereo_frontend.hpp"

namespace edx::frontend {
namespace {

struct Quality {
  int frames = 0;
  int features = 0;
  int stereo = 0, stereo_within_1px = 0;
  int tracks = 0, tracks_within_1px = 0;
  double stereo_fraction() const { return stereo > 0 ? double(stereo_within_1px) / stereo : 0; }
  double track_fraction() const { return tracks > 0 ? double(tracks_within_1px) / tracks : 0; }
};

/// Ray-cast truth for one frame's left camera.
class Truth {
 public:
  Truth(const synthetic::World& world, const synthetic::StereoRig& rig,
        const Eigen::Isometry3d& T_world_body)
      : world_(world), rig_(rig), T_world_left_(T_world_body * rig.T_body_left) {}

  /// World point seen at left pixel (u, v), and its depth; nullopt when the ray sees the sky.
  std::optional<std::pair<Eigen::Vector3d, double>> hit(double u, double v) const {
    const Eigen::Vector3d ray_cam((u - rig_.cx) / rig_.fx, (v - rig_.cy) / rig_.fy, 1.0);
    const Eigen::Vector3d dir_cam = ray_cam.normalized();
    const Eigen::Vector3d dir_world = T_world_left_.linear() * dir_cam;
    const synthetic::Hit h =
        world_.cast(T_world_left_.translation().cast<float>(), dir_world.cast<float>());
    if (!std::isfinite(h.t)) return std::nullopt;
    const double depth = static_cast<double>(h.t) * dir_cam.z();
    return std::make_pair(T_world_left_ * (static_cast<double>(h.t) * dir_cam), depth);
  }

  /// Pixel where world point X projects in this camera.
  Eigen::Vector2d project(const Eigen::Vector3d& X) const {
    const Eigen::Vector3d p = T_world_left_.inverse() * X;
    return {rig_.fx * p.x() / p.z() + rig_.cx, rig_.fy * p.y() / p.z() + rig_.cy};
  }

 private:
  const synthetic::World& world_;
  const synthetic::StereoRig& rig_;
  Eigen::Isometry3d T_world_left_;
};

Quality run_sequence(const synthetic::Scene& scene, const synthetic::StereoRig& rig, int frames,
                     std::uint64_t seed) {
  const std::vector<Eigen::Vector3d> body_points = {rig.T_body_left.translation(),
                                                    rig.T_body_right().translation()};
  const double period_s = 1.0 / synthetic::kCameraRateHz;
  const synthetic::PlannedTrajectory planned =
      synthetic::plan_trajectory(scene, period_s * frames, seed, body_points);
  synthetic::StereoCamera camera(scene.world, rig, synthetic::ImageSensorOptions{}, seed, 2);
  const FrontendOptions options;
  StereoFrontend frontend(options, {rig.fx, rig.baseline_m});

  Quality q;
  std::map<std::int64_t, Eigen::Vector3d> previous_points;  // track id -> world point seen
  for (int k = 0; k < frames; ++k) {
    const Eigen::Isometry3d T_world_body = planned.trajectory.at(k * period_s).T_world_body();
    const synthetic::StereoImages images = camera.capture(T_world_body);
    const FrontendFrame frame = frontend.process(images.left, images.right);
    const Truth truth(scene.world, rig, T_world_body);
    std::map<std::int64_t, Eigen::Vector3d> points;
    for (const Feature& f : frame.features) {
      ++q.features;
      const auto hit = truth.hit(f.left.x, f.left.y);
      if (f.age > 0) {
        if (const auto seen = previous_points.find(f.id); seen != previous_points.end()) {
          const Eigen::Vector2d expected = truth.project(seen->second);
          ++q.tracks;
          if ((expected - Eigen::Vector2d(f.left.x, f.left.y)).norm() < 1.0) ++q.tracks_within_1px;
        }
      }
      if (!hit) continue;
      points[f.id] = hit->first;
      if (f.stereo) {
        // The disparity is measured at the rounded left column (the SAD window centre).
        const auto centre = truth.hit(std::round(f.left.x), std::round(f.left.y));
        if (!centre) continue;
        ++q.stereo;
        const double expected = rig.fx * rig.baseline_m / centre->second;
        if (std::abs(f.disparity - expected) < 1.0) ++q.stereo_within_1px;
      }
    }
    previous_points = std::move(points);
    ++q.frames;
  }
  return q;
}

TEST(FrontendOnSyntheticWorld, WarehouseDroneRig) {
  const synthetic::Scene scene = synthetic::build_warehouse(11);
  const synthetic::StereoRig rig = synthetic::make_rig(
      synthetic::RigKind::kEuroc, synthetic::native_resolution(synthetic::RigKind::kEuroc));
  const Quality q = run_sequence(scene, rig, 8, 5);
  std::printf(
      "warehouse: %d frames, %d features, stereo %d (%.1f%% within 1 px), "
      "tracks %d (%.1f%% within 1 px)\n",
      q.frames, q.features, q.stereo, 100 * q.stereo_fraction(), q.tracks,
      100 * q.track_fraction());
  EXPECT_GT(q.stereo, 8 * 150);
  EXPECT_GT(q.tracks, 7 * 300);
  EXPECT_GE(q.stereo_fraction(), 0.90);
  EXPECT_GE(q.track_fraction(), 0.90);
}

TEST(FrontendOnSyntheticWorld, StreetCarRig) {
  const synthetic::Scene scene = synthetic::build_street(12);
  const synthetic::StereoRig rig = synthetic::make_rig(synthetic::RigKind::kCar, {640, 360});
  const Quality q = run_sequence(scene, rig, 8, 6);
  std::printf(
      "street: %d frames, %d features, stereo %d (%.1f%% within 1 px), "
      "tracks %d (%.1f%% within 1 px)\n",
      q.frames, q.features, q.stereo, 100 * q.stereo_fraction(), q.tracks,
      100 * q.track_fraction());
  EXPECT_GT(q.stereo, 8 * 100);
  EXPECT_GT(q.tracks, 7 * 200);
  EXPECT_GE(q.stereo_fraction(), 0.90);
  EXPECT_GE(q.track_fraction(), 0.90);
}

}  // namespace
}  // namespace edx::frontend
