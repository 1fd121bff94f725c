#include "workloads/backend/registration/bow/vocabulary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <utility>

#include "workloads/datasets/synthetic/random.hpp"

namespace edx::bow {

void VocabularyOptions::validate() const {
  auto fail = [](const std::string& what) {
    throw std::runtime_error("vocabulary options: " + what);
  };
  if (branching < 2 || branching > 64) {
    fail(fmt::format("branching = {}, expected 2..64", branching));
  }
  if (depth < 1 || depth > 16) fail(fmt::format("depth = {}, expected 1..16", depth));
  if (depth * std::log2(static_cast<double>(branching)) > 32.0) {
    fail(fmt::format("branching^depth = {}^{} exceeds 2^32 words", branching, depth));
  }
  if (max_iterations < 1) fail(fmt::format("max_iterations = {}, expected >= 1", max_iterations));
}

nlohmann::json VocabularyOptions::to_json() const {
  return {{"branching", branching},
          {"depth", depth},
          {"seed", seed},
          {"max_iterations", max_iterations}};
}

namespace {

struct Cluster {
  PackedDescriptor centroid;
  std::vector<std::uint32_t> members;  ///< indices into the descriptor set
};

/// Index of the nearest centre (ties: the lower index).
std::size_t nearest(const PackedDescriptor& d, const std::vector<PackedDescriptor>& centres) {
  std::size_t best = 0;
  int best_distance = 257;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    const int distance = hamming_distance(d, centres[c]);
    if (distance < best_distance) {
      best_distance = distance;
      best = c;
    }
  }
  return best;
}

/// k-majority clustering of `members` (Hamming k-medians): k-means++ seeding (Arthur and
/// Vassilvitskii 2007: next centre drawn with probability D(x)^2 / sum D^2, D the distance to
/// the nearest chosen centre; fewer than k centres when all remaining D are 0), then assignment
/// to the nearest centroid and bitwise-majority update until the centroids stop changing or
/// max_iterations updates ran. The returned members are assigned to the returned centroids.
std::vector<Cluster> k_majority(const std::vector<PackedDescriptor>& descriptors,
                                const std::vector<std::uint32_t>& members, int k,
                                int max_iterations, synthetic::Rng& rng, ClusteringStats& stats) {
  const std::size_t n = members.size();
  std::vector<PackedDescriptor> centres;
  centres.push_back(descriptors[members[rng() % n]]);
  std::vector<std::uint64_t> d2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto d =
        static_cast<std::uint64_t>(hamming_distance(descriptors[members[i]], centres[0]));
    d2[i] = d * d;
  }
  stats.distances += n;
  while (centres.size() < static_cast<std::size_t>(k)) {
    std::uint64_t total = 0;
    for (const std::uint64_t v : d2) total += v;
    if (total == 0) break;
    // Draw r uniform in [0, total) and take the first i whose cumulative D^2 exceeds it.
    const auto r = std::min(
        static_cast<std::uint64_t>(synthetic::uniform(rng, 0.0, static_cast<double>(total))),
        total - 1);
    std::uint64_t cumulative = 0;
    std::size_t pick = 0;
    for (; pick < n; ++pick) {
      cumulative += d2[pick];
      if (cumulative > r) break;
    }
    centres.push_back(descriptors[members[pick]]);
    for (std::size_t i = 0; i < n; ++i) {
      const auto d =
          static_cast<std::uint64_t>(hamming_distance(descriptors[members[i]], centres.back()));
      d2[i] = std::min(d2[i], d * d);
    }
    stats.distances += n;
  }

  std::vector<std::uint32_t> assignment(n);
  auto assign = [&] {
    for (std::size_t i = 0; i < n; ++i) {
      assignment[i] = static_cast<std::uint32_t>(nearest(descriptors[members[i]], centres));
    }
    stats.distances += n * centres.size();
    ++stats.iterations;
  };
  assign();
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    std::vector<BitCounter> counters(centres.size());
    for (std::size_t i = 0; i < n; ++i) counters[assignment[i]].add(descriptors[members[i]]);
    std::vector<PackedDescriptor> updated = centres;
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (counters[c].size() > 0) updated[c] = counters[c].majority();  // empty: keep
    }
    if (updated == centres) break;
    centres = std::move(updated);
    assign();
  }
  ++stats.node_splits;

  std::vector<Cluster> clusters(centres.size());
  for (std::size_t c = 0; c < centres.size(); ++c) clusters[c].centroid = centres[c];
  for (std::size_t i = 0; i < n; ++i) clusters[assignment[i]].members.push_back(members[i]);
  std::erase_if(clusters, [](const Cluster& c) { return c.members.empty(); });
  return clusters;
}

bool all_equal(const std::vector<PackedDescriptor>& descriptors,
               const std::vector<std::uint32_t>& members) {
  return std::all_of(members.begin(), members.end(), [&](std::uint32_t m) {
    return descriptors[m] == descriptors[members.front()];
  });
}

}  // namespace

Vocabulary Vocabulary::create(std::span<const Descriptor> descriptors,
                              const VocabularyOptions& options, ClusteringStats* stats_out) {
  options.validate();
  if (descriptors.empty()) throw std::runtime_error("vocabulary: no training descriptors");
  if (descriptors.size() >= kNoWord) throw std::runtime_error("vocabulary: too many descriptors");
  std::vector<PackedDescriptor> packed(descriptors.size());
  std::transform(descriptors.begin(), descriptors.end(), packed.begin(),
                 [](const Descriptor& d) { return pack(d); });

  ClusteringStats stats;
  stats.descriptors = packed.size();
  synthetic::Rng rng(synthetic::derive_seed(options.seed, "bow-k-majority"));

  std::vector<NodeId> parents{kNoParent};
  std::vector<PackedDescriptor> node_descriptors{PackedDescriptor{}};
  std::vector<int> levels{0};
  struct Pending {
    NodeId node;
    std::vector<std::uint32_t> members;
  };
  std::deque<Pending> queue;  // breadth first: the children of a node get consecutive ids
  {
    std::vector<std::uint32_t> all(packed.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    queue.push_back({0, std::move(all)});
  }
  while (!queue.empty()) {
    Pending pending = std::move(queue.front());
    queue.pop_front();
    const int level = levels[pending.node];
    if (level >= options.depth) continue;
    if (level > 0 && all_equal(packed, pending.members)) continue;
    std::vector<Cluster> clusters =
        k_majority(packed, pending.members, options.branching, options.max_iterations, rng, stats);
    for (Cluster& cluster : clusters) {
      const auto id = static_cast<NodeId>(parents.size());
      parents.push_back(pending.node);
      node_descriptors.push_back(cluster.centroid);
      levels.push_back(level + 1);
      queue.push_back({id, std::move(cluster.members)});
    }
  }
  if (stats_out) *stats_out = stats;

  std::vector<double> weights(parents.size(), 0.0);
  std::vector<bool> has_child(parents.size(), false);
  for (std::size_t i = 1; i < parents.size(); ++i) has_child[parents[i]] = true;
  for (std::size_t i = 1; i < parents.size(); ++i) weights[i] = has_child[i] ? 0.0 : 1.0;
  return from_nodes(options.branching, options.depth, std::move(parents),
                    std::move(node_descriptors), std::move(weights), "vocabulary");
}

Vocabulary Vocabulary::from_nodes(int branching, int depth, std::vector<NodeId> parents,
                                  std::vector<PackedDescriptor> descriptors,
                                  std::vector<double> weights, const std::string& context) {
  auto fail = [&](const std::string& what) { throw std::runtime_error(context + ": " + what); };
  if (parents.size() != descriptors.size() || parents.size() != weights.size()) {
    fail("node arrays of different sizes");
  }
  if (parents.size() < 2)
    fail(fmt::format("{} nodes, expected a root and at least one word", parents.size()));
  if (parents[0] != kNoParent)
    fail(fmt::format("node 0 has parent {}, expected none (root)", parents[0]));
  Vocabulary v;
  v.branching_ = branching;
  v.depth_ = depth;
  v.nodes_.resize(parents.size());
  for (std::size_t i = 0; i < parents.size(); ++i) {
    Node& node = v.nodes_[i];
    node.parent = parents[i];
    node.descriptor = descriptors[i];
    node.weight = weights[i];
    if (!std::isfinite(node.weight) || node.weight < 0) {
      fail(fmt::format("node {} has weight {}, expected a finite value >= 0", i, node.weight));
    }
    if (i == 0) continue;
    if (node.parent >= i) {
      fail(
          fmt::format("node {} has parent {}, expected a parent listed before it", i, node.parent));
    }
    node.level = v.nodes_[node.parent].level + 1;
    if (node.level > depth) {
      fail(fmt::format("node {} is at level {}, expected at most depth {}", i, node.level, depth));
    }
    if (++v.nodes_[node.parent].child_count > static_cast<std::uint32_t>(branching)) {
      fail(fmt::format("node {} has more than {} children", node.parent, branching));
    }
  }
  // Child lists (CSR, children in increasing id order) and words (leaves in node order).
  std::uint32_t offset = 0;
  for (Node& node : v.nodes_) {
    node.first_child = offset;
    offset += node.child_count;
  }
  v.child_ids_.resize(offset);
  std::vector<std::uint32_t> filled(v.nodes_.size(), 0);
  for (std::size_t i = 1; i < v.nodes_.size(); ++i) {
    const Node& parent = v.nodes_[v.nodes_[i].parent];
    v.child_ids_[parent.first_child + filled[v.nodes_[i].parent]++] = static_cast<NodeId>(i);
  }
  if (v.nodes_[0].child_count == 0) fail("the root has no children");
  v.child_descriptors_.resize(v.child_ids_.size());
  for (std::size_t c = 0; c < v.child_ids_.size(); ++c) {
    v.child_descriptors_[c] = v.nodes_[v.child_ids_[c]].descriptor;
  }
  for (std::size_t i = 1; i < v.nodes_.size(); ++i) {
    Node& node = v.nodes_[i];
    if (node.child_count > 0) {
      if (node.weight != 0) {
        fail(fmt::format("inner node {} has weight {}, expected 0", i, node.weight));
      }
      continue;
    }
    node.word = static_cast<WordId>(v.word_nodes_.size());
    v.word_nodes_.push_back(static_cast<NodeId>(i));
  }
  return v;
}

std::span<const NodeId> Vocabulary::children(NodeId node) const {
  const Node& n = nodes_.at(node);
  return {child_ids_.data() + n.first_child, n.child_count};
}

NodeId Vocabulary::descend(const PackedDescriptor& descriptor, int level,
                           NodeId* level_node) const {
  NodeId node = 0;
  while (nodes_[node].child_count > 0) {
    const Node& current = nodes_[node];
    NodeId best = child_ids_[current.first_child];
    int best_distance = 257;
    const PackedDescriptor* children = child_descriptors_.data() + current.first_child;
    for (std::uint32_t c = 0; c < current.child_count; ++c) {
      const int distance = hamming_distance(descriptor, children[c]);
      if (distance < best_distance) {
        best_distance = distance;
        best = child_ids_[current.first_child + c];
      }
    }
    node = best;
    if (level_node && nodes_[node].level <= level) *level_node = node;
  }
  return node;
}

WordId Vocabulary::word_of(const Descriptor& descriptor) const {
  if (empty()) return kNoWord;
  return nodes_[descend(pack(descriptor), 0, nullptr)].word;
}

std::vector<std::size_t> Vocabulary::set_idf(const std::vector<std::vector<Descriptor>>& images) {
  std::vector<std::size_t> images_with_word(word_count(), 0);
  if (empty()) return images_with_word;
  std::vector<std::size_t> last_image(word_count(), images.size());  // image that counted it
  for (std::size_t image = 0; image < images.size(); ++image) {
    for (const Descriptor& d : images[image]) {
      const WordId word = word_of(d);
      if (last_image[word] != image) {
        last_image[word] = image;
        ++images_with_word[word];
      }
    }
  }
  const auto n_images = static_cast<double>(images.size());
  for (WordId word = 0; word < word_count(); ++word) {
    const std::size_t n_i = images_with_word[word];
    nodes_[word_nodes_[word]].weight =
        n_i > 0 ? std::log(n_images / static_cast<double>(n_i)) : 0.0;
  }
  return images_with_word;
}

BowVector Vocabulary::transform(std::span<const Descriptor> descriptors) const {
  BowVector bow;
  FeatureVector unused;
  transform(descriptors, -1, bow, unused);
  return bow;
}

void Vocabulary::transform(std::span<const Descriptor> descriptors, int direct_index_level,
                           BowVector& bow, FeatureVector& features) const {
  const bool with_index = direct_index_level >= 0;
  if (with_index && (direct_index_level < 1 || direct_index_level > depth_)) {
    throw std::runtime_error(fmt::format(
        "vocabulary transform: direct index level {}, expected 1..{}", direct_index_level, depth_));
  }
  bow.clear();
  features.clear();
  if (empty() || descriptors.empty()) return;
  // v_i = (n_id / n_d) * idf_i, then v / |v|_1.
  const double tf_unit = 1.0 / static_cast<double>(descriptors.size());
  for (std::size_t i = 0; i < descriptors.size(); ++i) {
    NodeId level_node = 0;
    const Node& leaf = nodes_[descend(pack(descriptors[i]), direct_index_level,
                                      with_index ? &level_node : nullptr)];
    if (leaf.weight > 0) bow[leaf.word] += tf_unit * leaf.weight;
    if (with_index) features[level_node].push_back(static_cast<std::uint32_t>(i));
  }
  bow = l1_normalized(bow);
}

bool Vocabulary::operator==(const Vocabulary& other) const {
  if (branching_ != other.branching_ || depth_ != other.depth_ ||
      nodes_.size() != other.nodes_.size()) {
    return false;
  }
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& a = nodes_[i];
    const Node& b = other.nodes_[i];
    if (a.parent != b.parent || a.descriptor != b.descriptor || a.weight != b.weight) return false;
  }
  return true;
}

}  // namespace edx::bow
