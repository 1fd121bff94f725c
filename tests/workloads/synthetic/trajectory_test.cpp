// Trajectories: B-spline derivatives against finite differences, the body angular velocity
// against the rotation's own rate of change, motion limits of drone and car paths, clearance,
// determinism, and the revisit of the localization run.
#include "workloads/datasets/synthetic/trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "workloads/datasets/synthetic/random.hpp"
#include "workloads/datasets/synthetic/rig.hpp"
#include "workloads/datasets/synthetic/scenes.hpp"

namespace edx::synthetic {
namespace {

TEST(SyntheticSpline, LinearControlPointsGiveUniformMotion) {
  // P_k = a + b k: the uniform cubic B-spline reproduces the line, p(t) = a + b (s + 1),
  // s = (t - t0) / dt, so v = b / dt and zero acceleration.
  const Eigen::Vector3d a(1, -2, 0.5), b(0.3, 0.1, -0.2);
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 8; ++k) pts.push_back(a + b * k);
  const CubicBSpline spline(pts, 10.0, 0.5);
  EXPECT_DOUBLE_EQ(spline.t_begin(), 10.0);
  EXPECT_DOUBLE_EQ(spline.t_end(), 12.5);
  for (double t = 10.0; t <= 12.5; t += 0.1) {
    const auto s = spline.evaluate(t);
    EXPECT_LT((s.position - (a + b * ((t - 10.0) / 0.5 + 1))).norm(), 1e-12);
    EXPECT_LT((s.velocity - b / 0.5).norm(), 1e-12);
    EXPECT_LT(s.acceleration.norm(), 1e-12);
  }
  EXPECT_THROW(CubicBSpline({a, a, a}, 0, 1), std::runtime_error);
}

TEST(SyntheticSpline, DerivativesMatchFiniteDifferences) {
  Rng rng(3);
  std::vector<Eigen::Vector3d> pts;
  for (int k = 0; k < 12; ++k) pts.emplace_back(normal(rng), normal(rng), normal(rng));
  const CubicBSpline spline(pts, 0.0, 0.4);
  const double h = 1e-5;
  for (double t = 0.01; t < spline.t_end() - 0.01; t += 0.137) {
    const auto s = spline.evaluate(t);
    const auto sp = spline.evaluate(t + h), sm = spline.evaluate(t - h);
    EXPECT_LT((s.velocity - (sp.position - sm.position) / (2 * h)).norm(), 1e-6);
    EXPECT_LT((s.acceleration - (sp.velocity - sm.velocity) / (2 * h)).norm(), 1e-5);
  }
  // C2 at the knots: position, velocity and acceleration continuous.
  for (int k = 1; k < 9; ++k) {
    const double t = 0.4 * k;
    const auto l = spline.evaluate(t - 1e-9), r = spline.evaluate(t + 1e-9);
    EXPECT_LT((l.acceleration - r.acceleration).norm(), 1e-6);
  }
}

std::vector<Eigen::Vector3d> camera_points(RigKind kind) {
  const StereoRig rig = make_rig(kind, native_resolution(kind));
  return {rig.T_body_left.translation(), rig.T_body_right().translation()};
}

TEST(SyntheticTrajectory, RatesMatchFiniteDifferencesOfPoseAndVelocity) {
  const Scene scene = build_warehouse(1);
  const PlannedTrajectory planned = plan_trajectory(scene, 20.0, 9, camera_points(RigKind::kEuroc));
  const Trajectory& traj = planned.trajectory;
  const double h = 1e-4;
  for (double t = 0.05; t < 19.9; t += 0.31) {
    const BodyState s = traj.at(t), sp = traj.at(t + h), sm = traj.at(t - h);
    // omega_b = log(R(t-h)^T R(t+h)) / 2h.
    const Eigen::AngleAxisd delta(sm.R_world_body.transpose() * sp.R_world_body);
    const Eigen::Vector3d omega_fd = delta.axis() * delta.angle() / (2 * h);
    EXPECT_LT((s.omega_body - omega_fd).norm(), 1e-5) << "t " << t;
    EXPECT_LT((s.velocity - (sp.position - sm.position) / (2 * h)).norm(), 1e-6);
    EXPECT_LT((s.acceleration - (sp.velocity - sm.velocity) / (2 * h)).norm(), 1e-4);
    EXPECT_NEAR(s.R_world_body.determinant(), 1.0, 1e-12);
  }
}

TEST(SyntheticTrajectory, DroneFliesTheAislesAtDroneSpeeds) {
  const Scene scene = build_warehouse(2);
  const auto cams = camera_points(RigKind::kEuroc);
  const PlannedTrajectory planned = plan_trajectory(scene, 60.0, 4, cams);
  const Trajectory& traj = planned.trajectory;
  double length = 0, max_speed = 0, min_z = 1e9, max_z = -1e9, max_yaw_offset = 0;
  Eigen::Vector3d prev = traj.at(0).position;
  for (double t = 0; t <= 60.0; t += 0.05) {
    const BodyState s = traj.at(t);
    length += (s.position - prev).norm();
    prev = s.position;
    max_speed = std::max(max_speed, s.velocity.norm());
    min_z = std::min(min_z, s.position.z());
    max_z = std::max(max_z, s.position.z());
    // Yaw follows the horizontal velocity, within the wobble.
    const Eigen::Vector3d forward = s.R_world_body.col(0);
    const double heading = std::atan2(s.velocity.y(), s.velocity.x());
    const double yaw = std::atan2(forward.y(), forward.x());
    max_yaw_offset = std::max(max_yaw_offset, std::abs(std::remainder(yaw - heading, 2 * M_PI)));
    EXPECT_GE(scene.world.distance_to_geometry(s.position), scene.motion.clearance_m);
    for (const auto& c : cams) {
      EXPECT_GE(scene.world.distance_to_geometry(s.T_world_body() * c), scene.motion.clearance_m);
    }
  }
  const double mean_speed = length / 60.0;
  EXPECT_GE(mean_speed, 1.0);
  EXPECT_LE(mean_speed, 2.0);
  EXPECT_LE(max_speed, 2.3);
  EXPECT_GE(min_z, scene.motion.min_height_m - 0.05);
  EXPECT_LE(max_z, scene.motion.max_height_m + 0.05);
  EXPECT_GT(max_z - min_z, 0.3);  // some height changes
  EXPECT_LT(max_yaw_offset, 0.16);
  EXPECT_GT(max_yaw_offset, 0.02);  // some wobble
  EXPECT_GE(planned.route.size(), 3u);
}

TEST(SyntheticTrajectory, CarDrivesTheRightLaneOnTheRoadPlane) {
  const Scene scene = build_street(2);
  const PlannedTrajectory planned = plan_trajectory(scene, 60.0, 4, camera_points(RigKind::kCar));
  const Trajectory& traj = planned.trajectory;
  double length = 0, max_speed = 0, min_speed = 1e9, max_tilt = 0, max_yaw_offset = 0;
  Eigen::Vector3d prev = traj.at(0).position;
  for (double t = 0; t <= 60.0; t += 0.05) {
    const BodyState s = traj.at(t);
    length += (s.position - prev).norm();
    prev = s.position;
    const double speed = s.velocity.norm();
    max_speed = std::max(max_speed, speed);
    min_speed = std::min(min_speed, speed);
    EXPECT_NEAR(s.position.z(), 0.9, 1e-9);
    const Eigen::Vector3d forward = s.R_world_body.col(0);
    const Eigen::Vector3d up = s.R_world_body.col(2);
    max_tilt = std::max(max_tilt, std::acos(std::min(1.0, up.z())));
    const double heading = std::atan2(s.velocity.y(), s.velocity.x());
    max_yaw_offset = std::max(
        max_yaw_offset,
        std::abs(std::remainder(std::atan2(forward.y(), forward.x()) - heading, 2 * M_PI)));
  }
  const double mean_speed = length / 60.0;
  EXPECT_GE(mean_speed, 5.0);
  EXPECT_LE(mean_speed, 15.0);
  EXPECT_LE(max_speed, 15.0);
  EXPECT_GE(min_speed, 3.0);
  EXPECT_LT(max_tilt, 2.0 * M_PI / 180);
  EXPECT_LT(max_yaw_offset, 0.5 * M_PI / 180);
  // At least one turn at a junction in a minute of driving.
  EXPECT_GE(planned.route.size(), 4u);
}

TEST(SyntheticTrajectory, DeterministicBySeed) {
  const Scene scene = build_street(5);
  const auto cams = camera_points(RigKind::kCar);
  const PlannedTrajectory a = plan_trajectory(scene, 10.0, 77, cams);
  const PlannedTrajectory b = plan_trajectory(scene, 10.0, 77, cams);
  const PlannedTrajectory c = plan_trajectory(scene, 10.0, 78, cams);
  double diff_same = 0, diff_other = 0;
  for (double t = 0; t <= 10.0; t += 0.5) {
    diff_same += (a.trajectory.at(t).position - b.trajectory.at(t).position).norm();
    diff_other += (a.trajectory.at(t).position - c.trajectory.at(t).position).norm();
  }
  EXPECT_EQ(diff_same, 0.0);
  EXPECT_GT(diff_other, 1.0);
}

TEST(SyntheticTrajectory, RevisitStartsOnTheEarlierRouteAndLeavesDifferently) {
  const Scene scene = build_warehouse(3);
  const auto cams = camera_points(RigKind::kEuroc);
  const PlannedTrajectory first = plan_trajectory(scene, 60.0, 21, cams);
  Revisit diverge;
  diverge.route = first.route;
  diverge.mode = RevisitMode::kDiverge;
  const PlannedTrajectory second = plan_trajectory(scene, 60.0, 22, cams, &diverge);
  const std::size_t idx = first.route.size() / 3;
  EXPECT_EQ(second.route.front(), first.route[idx]);
  EXPECT_NE(second.route[1], first.route[idx + 1]);
  EXPECT_THROW(plan_trajectory(scene, 0.0, 1, cams), std::runtime_error);
}

// The default revisit re-traverses the earlier route in the same direction: same lane-graph
// nodes first, positions within the lateral offset plus both runs' wander (+-0.45 m each) of the
// earlier path, heading the same way; its speeds are the drawn ones times speed_scale.
TEST(SyntheticTrajectory, RetraverseFollowsTheEarlierRouteOffsetAndSlower) {
  const Scene scene = build_warehouse(3);
  const auto cams = camera_points(RigKind::kEuroc);
  const double duration = 20.0;
  const PlannedTrajectory first = plan_trajectory(scene, duration, 21, cams);
  Revisit revisit;
  revisit.route = first.route;
  const PlannedTrajectory second = plan_trajectory(scene, duration, 22, cams, &revisit);
  ASSERT_GE(second.route.size(), first.route.size());
  EXPECT_TRUE(std::equal(first.route.begin(), first.route.end(), second.route.begin()));
  std::vector<BodyState> path;
  for (double t = 0; t <= duration; t += 0.02) path.push_back(first.trajectory.at(t));
  double worst = 0;
  int compared = 0;
  for (double t = 0; t <= duration; t += 0.1) {
    const BodyState s = second.trajectory.at(t);
    double best = 1e9;
    std::size_t nearest = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
      const double d = (path[i].position - s.position).head<2>().norm();
      if (d < best) best = d, nearest = i;
    }
    if (nearest + 1 == path.size()) continue;  // past the end of the earlier run
    ++compared;
    worst = std::max(worst, best);
    EXPECT_GT(s.velocity.head<2>().normalized().dot(path[nearest].velocity.head<2>().normalized()),
              0.5)
        << "t = " << t;
  }
  EXPECT_GT(compared, 100);
  EXPECT_LT(worst, 0.3 + 2 * 0.45 + 0.05);  // lateral offset + both wanders (+ sampling)
  // Same seed at full speed: the speed scale shortens the path by about its factor.
  Revisit full = revisit;
  full.speed_scale = 1.0;
  const PlannedTrajectory unscaled = plan_trajectory(scene, duration, 22, cams, &full);
  ASSERT_EQ(unscaled.attempts, second.attempts);  // the same draws: only the scale differs
  const auto length = [&](const Trajectory& traj) {
    double l = 0;
    for (double t = 0.05; t <= duration; t += 0.05)
      l += (traj.at(t).position - traj.at(t - 0.05).position).norm();
    return l;
  };
  EXPECT_NEAR(length(second.trajectory) / length(unscaled.trajectory), 0.85, 0.05);
  Revisit bad = revisit;
  bad.speed_scale = 0.1;
  EXPECT_THROW(plan_trajectory(scene, duration, 22, cams, &bad), std::runtime_error);
}

}  // namespace
}  // namespace edx::synthetic
