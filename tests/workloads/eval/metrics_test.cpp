// Metrics against hand-computed values: rotation angles, path distances, RPE and KITTI segment
// errors on a straight 200 m line.
#include "workloads/eval/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/workloads/eval/eval_test_support.hpp"

namespace edx::eval {
namespace {

using testing::make_pose;
using testing::rot_y;
using testing::rot_z;

constexpr double kPi = std::numbers::pi;

/// Poses along the camera's forward axis z, 1 m apart: frames 0..200 span 200 m.
std::vector<Pose> straight_line(double metres_per_frame = 1.0, std::size_t frames = 201) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < frames; ++i) {
    poses.push_back(make_pose(Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d(0, 0, metres_per_frame * static_cast<double>(i))));
  }
  return poses;
}

std::vector<std::optional<Pose>> all_present(const std::vector<Pose>& poses) {
  return {poses.begin(), poses.end()};
}

TEST(Metrics, SummarizeErrors) {
  const ErrorStats stats = summarize_errors({3.0, 1.0, 4.0, 1.0});
  EXPECT_EQ(stats.count, 4u);
  EXPECT_DOUBLE_EQ(stats.mean, 2.25);
  EXPECT_DOUBLE_EQ(stats.rmse, std::sqrt((9.0 + 1.0 + 16.0 + 1.0) / 4.0));
  EXPECT_DOUBLE_EQ(stats.median, 2.0);
  EXPECT_DOUBLE_EQ(stats.max, 4.0);
  EXPECT_EQ(summarize_errors({}).count, 0u);
}

TEST(Metrics, RotationAngleIsClampedLikeTheDevkit) {
  EXPECT_NEAR(rotation_angle_rad(rot_z(0.3)), 0.3, 1e-12);
  EXPECT_NEAR(rotation_angle_rad(rot_y(-2.0)), 2.0, 1e-12);
  // trace slightly above 3 (rounding) gives 0, not NaN.
  EXPECT_EQ(rotation_angle_rad(Eigen::Matrix3d::Identity() * (1.0 + 1e-12)), 0.0);
  EXPECT_NEAR(rotation_angle_rad(-Eigen::Matrix3d::Identity() * (1.0 + 1e-12)), kPi, 1e-12);
}

TEST(Metrics, PathDistancesAndPairsAtDistance) {
  const std::vector<double> d = path_distances(straight_line(0.5, 11));  // 0, 0.5, ..., 5 m
  ASSERT_EQ(d.size(), 11u);
  EXPECT_DOUBLE_EQ(d[10], 5.0);
  // The first j with d_j > d_i + 2 (strictly): i + 5.
  const std::vector<FramePair> pairs = pairs_at_distance(d, 2.0);
  ASSERT_EQ(pairs.size(), 6u);  // starts 0..5 (5 -> 10)
  EXPECT_EQ(pairs[0].second, 5u);
  EXPECT_EQ(pairs[5].first, 5u);
  EXPECT_EQ(pairs[5].second, 10u);
  EXPECT_EQ(consecutive_pairs(3).size(), 2u);
}

TEST(Metrics, RelativePoseErrorOfAKnownMotion) {
  // gt moves 1 m forward; est moves 1.2 m forward and turns 0.1 rad about y.
  const Pose origin = Pose::Identity();
  const Pose gt_b = make_pose(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 1));
  const Pose est_b = make_pose(rot_y(0.1), Eigen::Vector3d(0, 0, 1.2));
  const PoseError error = relative_pose_error(origin, gt_b, origin, est_b);
  EXPECT_NEAR(error.translation_m, 0.2, 1e-12);  // E = [Ry(0.1) | (0, 0, 0.2)]
  EXPECT_NEAR(error.rotation_rad, 0.1, 1e-12);
}

TEST(Metrics, KittiSegmentOnAStraightLineWithAScaleError) {
  // est travels 2 % further than gt. On a 1 m-spaced 200 m line the only segments are the 100 m
  // ones (no frame lies beyond 200 m), starting at frames 0, 10, ..., 90; each ends at the first
  // frame with d > d_first + 100, i.e. 101 frames later. gt moves 101 m, est 103.02 m:
  //   t_err = |101 - 103.02| / 100 = 2.02 %,  r_err = 0.
  const std::vector<Pose> gt = straight_line();
  std::vector<Pose> est = gt;
  for (auto& pose : est) pose.translation() *= 1.02;
  const auto segments = kitti_segment_errors(gt, all_present(est));
  ASSERT_EQ(segments.size(), 10u);
  EXPECT_EQ(segments.front().first, 0u);
  EXPECT_EQ(segments.front().last, 101u);
  EXPECT_EQ(segments.back().first, 90u);
  const KittiSummary summary = summarize_kitti_segments(segments);
  EXPECT_EQ(summary.segments, 10u);
  EXPECT_NEAR(*summary.t_err_pct, 2.02, 1e-12);
  EXPECT_NEAR(*summary.r_err_deg_per_100m, 0.0, 1e-12);
  ASSERT_EQ(summary.by_length.size(), 1u);
  EXPECT_EQ(summary.by_length[0].length_m, 100.0);
}

TEST(Metrics, KittiSegmentRotationErrorInDegreesPer100m) {
  // est turns 0.001 rad about y per frame while gt goes straight: over a segment of 101 frames the
  // rotation error is 0.101 rad per 100 m = 0.101 * 180 / pi deg / 100 m.
  const std::vector<Pose> gt = straight_line();
  std::vector<Pose> est = gt;
  for (std::size_t i = 0; i < est.size(); ++i) est[i].linear() = rot_y(0.001 * double(i));
  const KittiSummary summary = summarize_kitti_segments(kitti_segment_errors(gt, all_present(est)));
  EXPECT_NEAR(*summary.r_err_deg_per_100m, 0.101 * 180.0 / kPi, 1e-9);
}

TEST(Metrics, KittiSegmentsNeedAnEstimateAtBothEnds) {
  const std::vector<Pose> gt = straight_line();
  auto est = all_present(gt);
  est[0].reset();    // the segment 0 -> 101 loses its start
  est[111].reset();  // the segment 10 -> 111 loses its end
  const KittiSummary summary = summarize_kitti_segments(kitti_segment_errors(gt, est));
  EXPECT_EQ(summary.segments, 8u);
  EXPECT_NEAR(*summary.t_err_pct, 0.0, 1e-12);
  // A 50 m line has no 100 m segment at all: no figure rather than a zero.
  const auto short_line = straight_line(1.0, 51);
  const KittiSummary none =
      summarize_kitti_segments(kitti_segment_errors(short_line, all_present(short_line)));
  EXPECT_EQ(none.segments, 0u);
  EXPECT_FALSE(none.t_err_pct.has_value());
}

}  // namespace
}  // namespace edx::eval
