// Association of estimated with ground-truth poses: by frame index, and by nearest timestamp
// within --t-max-diff with every pose used at most once.
#include "workloads/eval/association.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>
#include <vector>

namespace edx::eval {
namespace {

using ::testing::HasSubstr;

Trajectory stamped(const std::string& source, StampKind kind, const std::vector<double>& keys) {
  Trajectory trajectory;
  trajectory.source = source;
  trajectory.stamp_kind = kind;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    StampedPose pose;
    pose.time_s = keys[i];
    pose.frame_index = kind == StampKind::kFrameIndex ? static_cast<std::int64_t>(keys[i])
                                                      : static_cast<std::int64_t>(i);
    pose.line = i + 1;
    trajectory.poses.push_back(pose);
  }
  return trajectory;
}

std::vector<std::pair<std::size_t, std::size_t>> as_pairs(const Association& association) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& pair : association.pairs) pairs.emplace_back(pair.gt, pair.est);
  return pairs;
}

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

TEST(Association, ByFrameIndexSkipsFramesWithoutGroundTruth) {
  const auto gt = stamped("gt.txt", StampKind::kFrameIndex, {0, 1, 2, 3, 4, 5});
  const auto est = stamped("est.txt", StampKind::kFrameIndex, {2, 3, 5, 9});
  const Association association = associate(gt, est, 0.0);
  EXPECT_EQ(as_pairs(association), (Pairs{{2, 0}, {3, 1}, {5, 2}}));
  EXPECT_EQ(association.est_unmatched, 1u);  // frame 9
}

TEST(Association, ByFrameIndexWithoutCommonFramesIsAnError) {
  const auto gt = stamped("gt.txt", StampKind::kFrameIndex, {0, 1});
  const auto est = stamped("est.txt", StampKind::kFrameIndex, {5, 6});
  try {
    associate(gt, est, 0.0);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "no frame index of est.txt (frames 5..6) is in gt.txt (0..1)");
  }
}

TEST(Association, ByTimeTakesTheNearestWithinTolerance) {
  // gt at 100 Hz; est offset by +3 ms, +12 ms (too far for 5 ms), -4 ms.
  const auto gt = stamped("gt.tum", StampKind::kSeconds, {0.00, 0.01, 0.02, 0.03, 0.04, 0.05});
  const auto est = stamped("est.tum", StampKind::kSeconds, {0.013, 0.032, 0.046});
  const Association tight = associate(gt, est, 0.005);
  EXPECT_EQ(as_pairs(tight), (Pairs{{1, 0}, {3, 1}, {5, 2}}));
  EXPECT_EQ(tight.est_unmatched, 0u);
  const Association tighter = associate(gt, est, 0.0035);  // 0.046 is 4 ms from 0.05
  EXPECT_EQ(as_pairs(tighter), (Pairs{{1, 0}, {3, 1}}));
  EXPECT_EQ(tighter.est_unmatched, 1u);
}

TEST(Association, ByTimeUsesEachGroundTruthPoseOnce) {
  // Both estimates are nearest to gt 1.0; the closer one (1.01) wins it, the other takes 0.5.
  const auto gt = stamped("gt.tum", StampKind::kSeconds, {0.5, 1.0, 2.0});
  const auto est = stamped("est.tum", StampKind::kSeconds, {0.9, 1.01});
  EXPECT_EQ(as_pairs(associate(gt, est, 0.45)), (Pairs{{0, 0}, {1, 1}}));
  // With a tolerance too tight for 0.5, the loser stays unmatched instead of sharing gt 1.0.
  const Association tight = associate(gt, est, 0.2);
  EXPECT_EQ(as_pairs(tight), (Pairs{{1, 1}}));
  EXPECT_EQ(tight.est_unmatched, 1u);
}

TEST(Association, ByTimeBreaksTiesTowardsTheEarlierPose) {
  // 0.125 is exactly 0.125 s from both 0 and 0.25 (all exact in binary): the earlier gt wins.
  const auto gt = stamped("gt.tum", StampKind::kSeconds, {0.0, 0.25});
  const auto est = stamped("est.tum", StampKind::kSeconds, {0.125});
  EXPECT_EQ(as_pairs(associate(gt, est, 0.2)), (Pairs{{0, 0}}));
}

TEST(Association, NoOverlapInTimeIsAnError) {
  const auto gt = stamped("gt.tum", StampKind::kSeconds, {0.0, 1.0});
  const auto est = stamped("est.tum", StampKind::kSeconds, {5.0, 6.0});
  try {
    associate(gt, est, 0.02);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(),
                 "no overlap in time: gt.tum covers [0.000000000, 1.000000000] s, est.tum covers "
                 "[5.000000000, 6.000000000] s");
  }
}

TEST(Association, OverlapWithoutAnyPairWithinToleranceIsAnError) {
  const auto gt = stamped("gt.tum", StampKind::kSeconds, {0.0, 1.0});
  const auto est = stamped("est.tum", StampKind::kSeconds, {0.5});
  try {
    associate(gt, est, 0.02);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "no pose of est.tum is within 0.02 s of a pose of gt.tum");
  }
}

TEST(Association, MixedStampKindsAndBadToleranceAreErrors) {
  const auto gt = stamped("gt.txt", StampKind::kFrameIndex, {0, 1});
  const auto est = stamped("est.tum", StampKind::kSeconds, {0.0});
  EXPECT_THAT([&] { associate(gt, est, 0.02); },
              ::testing::ThrowsMessage<std::runtime_error>(HasSubstr("stamped differently")));
  const auto est_seconds = stamped("est.tum", StampKind::kSeconds, {0.0});
  const auto gt_seconds = stamped("gt.tum", StampKind::kSeconds, {0.0});
  EXPECT_THROW(associate_by_time(gt_seconds, est_seconds, -1.0), std::runtime_error);
}

}  // namespace
}  // namespace edx::eval
