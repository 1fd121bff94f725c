// The covisibility graph and ORB-SLAM's local map on a hand-built map: four keyframes along a
// corridor, each observing a window of 40 points that overlaps its neighbour's by 20.
#include "workloads/backend/registration/covisibility.hpp"

#include <gtest/gtest.h>

namespace edx::backend::registration {
namespace {

/// Keyframe k (id 10 + k) observes points 20k .. 20k + 39 (100 points in all, 0..99).
slam::Map corridor() {
  slam::Map map;
  for (int k = 0; k < 4; ++k) {
    slam::MapKeyframe kf;
    kf.id = 10 + k;
    map.keyframes.push_back(kf);
  }
  for (int i = 0; i < 100; ++i) {
    slam::MapLandmark l;
    l.id = i;
    for (int k = 0; k < 4; ++k) {
      if (i >= 20 * k && i < 20 * k + 40) l.observations.push_back({10 + k, 0});
    }
    map.landmarks.push_back(l);
  }
  return map;
}

TEST(CovisibilityGraph, EdgesCountSharedPoints) {
  const CovisibilityGraph g(corridor(), LocalMapOptions{});
  EXPECT_EQ(g.points_of(0).size(), 40u);
  EXPECT_EQ(g.points_of(3).size(), 40u);  // points 60..99
  EXPECT_EQ(g.keyframes_of(25), (std::vector<std::size_t>{0, 1}));
  // Neighbours share 20 points (an edge at >= 15); keyframes two apart share none.
  ASSERT_EQ(g.covisible(1).size(), 2u);
  EXPECT_EQ(g.covisible(1)[0], (std::pair<std::size_t, int>{0, 20}));
  EXPECT_EQ(g.covisible(1)[1], (std::pair<std::size_t, int>{2, 20}));
  // Above the threshold no edge is kept but the best neighbour.
  LocalMapOptions strict;
  strict.min_shared = 30;
  const CovisibilityGraph s(corridor(), strict);
  ASSERT_EQ(s.covisible(1).size(), 1u);
  EXPECT_EQ(s.covisible(1)[0].first, 0u);
}

TEST(CovisibilityGraph, LocalMapIsTheAnchorsKeyframesAndOneNeighbourEach) {
  const CovisibilityGraph g(corridor(), LocalMapOptions{});
  // Anchors 0..9 are seen by keyframe 0 only: K1 = {0}, plus its best neighbour 1.
  std::vector<std::size_t> anchors{0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  LocalMap local = g.local_map(anchors);
  EXPECT_EQ(local.keyframes, (std::vector<std::size_t>{0, 1}));
  ASSERT_EQ(local.points.size(), 60u);  // points 0..59
  EXPECT_EQ(local.points.front(), 0u);
  EXPECT_EQ(local.points.back(), 59u);
  // Anchors 41..59 and 65: keyframe 2 sees 20 of them, keyframe 1 19, keyframe 3 one; K1 =
  // {2, 1, 3} by count; then one new neighbour each: 2's (1 and 3) are taken, 1 adds 0.
  anchors.clear();
  for (std::size_t i = 41; i <= 59; ++i) anchors.push_back(i);
  anchors.push_back(65);
  local = g.local_map(anchors);
  EXPECT_EQ(local.keyframes, (std::vector<std::size_t>{2, 1, 3, 0}));
  EXPECT_EQ(local.points.size(), 100u);
  // The bound on the local keyframes.
  LocalMapOptions one;
  one.max_keyframes = 1;
  local = CovisibilityGraph(corridor(), one).local_map(anchors);
  EXPECT_EQ(local.keyframes, (std::vector<std::size_t>{2}));
  EXPECT_EQ(local.points.size(), 40u);
  // No anchors (or unknown ones): nothing to project.
  EXPECT_TRUE(g.local_map({}).points.empty());
  EXPECT_TRUE(g.local_map({1000}).keyframes.empty());
}

}  // namespace
}  // namespace edx::backend::registration
