#pragma once
// The map's covisibility graph and ORB-SLAM's local map (Mur-Artal et al., ORB-SLAM,
// Tracking::UpdateLocalKeyFrames / UpdateLocalPoints), which the registration backend projects
// every frame: "the current map" of the paper's projection kernel (Sec. VI-B: its latency grows
// with the number of points in the current map).
//
//   covisibility weight w(i, j) = number of map points both keyframes i and j observe; an edge
//     when w >= min_shared (ORB-SLAM: 15; a keyframe with no such neighbour keeps its best one)
//   K1 = keyframes observing any of the anchor points (the map points the previous frame
//     matched), ordered by how many anchors each observes (ties: map order)
//   local keyframes = K1, then for each keyframe of K1 in order, while there are fewer than
//     max_keyframes (ORB-SLAM: 80), the first of its `neighbours` (10) best covisible
//     keyframes not yet taken (ORB-SLAM adds one per keyframe); the spanning tree's parent and
//     children that ORB-SLAM also adds do not exist in an edx map and are left out
//   local points = every map point the local keyframes observe, each once, in index order
#include <cstddef>
#include <vector>

#include "workloads/backend/slam/map.hpp"

namespace edx::backend::registration {

struct LocalMapOptions {
  int min_shared = 15;             ///< covisibility edge threshold (shared map points)
  std::size_t neighbours = 10;     ///< best covisible keyframes looked at per K1 keyframe
  std::size_t max_keyframes = 80;  ///< local keyframes at most
};

struct LocalMap {
  std::vector<std::size_t> keyframes;  ///< map keyframe indices (map order of `slam::Map`)
  std::vector<std::size_t> points;     ///< map landmark indices, increasing
};

class CovisibilityGraph {
 public:
  /// Builds the graph of `map` (keyframes and landmarks by their index in the map; observations
  /// of unknown keyframes are ignored).
  CovisibilityGraph(const slam::Map& map, const LocalMapOptions& options);

  /// Landmarks observed by keyframe k, increasing.
  const std::vector<std::size_t>& points_of(std::size_t k) const { return points_of_[k]; }
  /// Keyframes observing landmark i, increasing.
  const std::vector<std::size_t>& keyframes_of(std::size_t i) const { return keyframes_of_[i]; }
  /// Keyframes linked to k by an edge, by weight (decreasing; ties: map order).
  const std::vector<std::pair<std::size_t, int>>& covisible(std::size_t k) const {
    return covisible_[k];
  }
  /// The local map around the anchor landmarks (indices into the map's landmarks).
  LocalMap local_map(const std::vector<std::size_t>& anchor_points) const;

 private:
  LocalMapOptions options_;
  std::vector<std::vector<std::size_t>> points_of_, keyframes_of_;
  std::vector<std::vector<std::pair<std::size_t, int>>> covisible_;
};

}  // namespace edx::backend::registration
