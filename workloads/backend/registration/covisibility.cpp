#include "workloads/backend/registration/covisibility.hpp"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace edx::backend::registration {

CovisibilityGraph::CovisibilityGraph(const slam::Map& map, const LocalMapOptions& options)
    : options_(options),
      points_of_(map.keyframes.size()),
      keyframes_of_(map.landmarks.size()),
      covisible_(map.keyframes.size()) {
  std::unordered_map<std::int64_t, std::size_t> index_of;
  for (std::size_t k = 0; k < map.keyframes.size(); ++k) index_of[map.keyframes[k].id] = k;
  for (std::size_t i = 0; i < map.landmarks.size(); ++i) {
    for (const slam::MapObservation& o : map.landmarks[i].observations) {
      const auto it = index_of.find(o.keyframe_id);
      if (it == index_of.end()) continue;
      keyframes_of_[i].push_back(it->second);
    }
    std::sort(keyframes_of_[i].begin(), keyframes_of_[i].end());
    keyframes_of_[i].erase(std::unique(keyframes_of_[i].begin(), keyframes_of_[i].end()),
                           keyframes_of_[i].end());
    for (std::size_t k : keyframes_of_[i]) points_of_[k].push_back(i);
  }
  // w(i, j): shared points, counted over each point's observers.
  std::vector<std::map<std::size_t, int>> weights(map.keyframes.size());
  for (const std::vector<std::size_t>& observers : keyframes_of_) {
    for (std::size_t a = 0; a < observers.size(); ++a) {
      for (std::size_t b = a + 1; b < observers.size(); ++b) {
        ++weights[observers[a]][observers[b]];
        ++weights[observers[b]][observers[a]];
      }
    }
  }
  for (std::size_t k = 0; k < weights.size(); ++k) {
    std::vector<std::pair<std::size_t, int>> edges(weights[k].begin(), weights[k].end());
    std::stable_sort(edges.begin(), edges.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    // Edges at or above the threshold; a keyframe without one keeps its best neighbour.
    std::size_t keep = 0;
    while (keep < edges.size() && edges[keep].second >= options_.min_shared) ++keep;
    if (keep == 0 && !edges.empty()) keep = 1;
    edges.resize(keep);
    covisible_[k] = std::move(edges);
  }
}

LocalMap CovisibilityGraph::local_map(const std::vector<std::size_t>& anchor_points) const {
  // K1 with how many anchors each keyframe observes.
  std::map<std::size_t, int> counter;
  for (std::size_t i : anchor_points) {
    if (i >= keyframes_of_.size()) continue;
    for (std::size_t k : keyframes_of_[i]) ++counter[k];
  }
  std::vector<std::pair<std::size_t, int>> k1(counter.begin(), counter.end());
  std::stable_sort(k1.begin(), k1.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  LocalMap local;
  std::vector<bool> taken(points_of_.size(), false);
  for (const auto& [k, count] : k1) {
    if (local.keyframes.size() >= options_.max_keyframes) break;
    local.keyframes.push_back(k);
    taken[k] = true;
  }
  // One new covisible neighbour per K1 keyframe (ORB-SLAM's loop breaks after the first).
  const std::size_t k1_size = local.keyframes.size();
  for (std::size_t j = 0; j < k1_size && local.keyframes.size() < options_.max_keyframes; ++j) {
    const auto& neighbours = covisible_[local.keyframes[j]];
    const std::size_t n = std::min(options_.neighbours, neighbours.size());
    for (std::size_t e = 0; e < n; ++e) {
      const std::size_t other = neighbours[e].first;
      if (taken[other]) continue;
      taken[other] = true;
      local.keyframes.push_back(other);
      break;
    }
  }
  std::vector<bool> point_taken(keyframes_of_.size(), false);
  for (std::size_t k : local.keyframes) {
    for (std::size_t i : points_of_[k]) point_taken[i] = true;
  }
  for (std::size_t i = 0; i < point_taken.size(); ++i) {
    if (point_taken[i]) local.points.push_back(i);
  }
  return local;
}

}  // namespace edx::backend::registration
