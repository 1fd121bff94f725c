#pragma once
// A DBoW2-style visual vocabulary of ORB descriptors (Galvez-Lopez and Tardos 2012; the
// vocabulary of ORB-SLAM, Mur-Artal et al.): a tree built by hierarchical k-majority clustering
// (k-medians in Hamming space with bitwise-majority centroids, k-means++ seeding), branching k,
// depth L; its leaves are the words, weighted by their inverse document frequency
//   idf_i = ln(N / n_i)   (N training images, n_i of them containing word i; 0 when n_i = 0)
// An image's descriptors become the TF-IDF vector v_i = (n_id / n_d) * idf_i (n_id of its n_d
// features fall in word i), normalised to |v|_1 = 1. A descriptor descends from the root to a
// leaf through the nearest child at each level: at most L * k Hamming distances.
//
// Nodes are numbered breadth first; node 0 is the root (no descriptor). A node becomes a leaf
// at depth L, or earlier when all its descriptors are equal (splitting it would only chain
// copies down to depth L, as DBoW2 does).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "workloads/backend/registration/bow/bow_vector.hpp"
#include "workloads/backend/registration/bow/descriptor.hpp"

namespace edx::bow {

struct VocabularyOptions {
  int branching = 10;       ///< k: children per node (ORB-SLAM: 10)
  int depth = 5;            ///< L: levels below the root; up to k^L words (ORB-SLAM: 6)
  std::uint64_t seed = 1;   ///< k-means++ seeding and descriptor subsampling
  int max_iterations = 20;  ///< k-majority iterations per node (it stops earlier when stable)

  /// Throws std::runtime_error naming the first field out of range: branching in [2, 64],
  /// depth in [1, 16], branching^depth <= 2^32, max_iterations >= 1.
  void validate() const;
  nlohmann::json to_json() const;
};

/// Counts of one clustering run (Vocabulary::create).
struct ClusteringStats {
  std::size_t descriptors = 0;  ///< descriptors clustered
  std::size_t node_splits = 0;  ///< nodes k-majority clustering ran on
  std::size_t iterations = 0;   ///< assignment passes summed over those nodes
  std::size_t distances = 0;    ///< Hamming distances computed
};

class Vocabulary {
 public:
  static constexpr NodeId kNoParent = 0xFFFFFFFFu;
  static constexpr WordId kNoWord = 0xFFFFFFFFu;

  /// An empty vocabulary (no words); transform gives empty vectors.
  Vocabulary() = default;

  /// Builds the tree over `descriptors` (all word weights 1 until set_idf). Deterministic for
  /// the options' seed. Throws std::runtime_error on invalid options or no descriptors.
  static Vocabulary create(std::span<const Descriptor> descriptors,
                           const VocabularyOptions& options, ClusteringStats* stats = nullptr);

  /// Sets each word's weight to idf_i = ln(N / n_i) over `images` (each the descriptors of one
  /// training image), 0 for words no image contains. Returns n_i per word.
  std::vector<std::size_t> set_idf(const std::vector<std::vector<Descriptor>>& images);

  /// The word a descriptor falls in: greedy descent through the nearest child (ties: the lower
  /// node id). kNoWord for an empty vocabulary.
  WordId word_of(const Descriptor& descriptor) const;

  /// TF-IDF vector of one image, L1-normalised (words of weight 0 are left out, as DBoW2 does).
  BowVector transform(std::span<const Descriptor> descriptors) const;
  /// Also fills the direct index: for every feature, the node at `direct_index_level` (1..L,
  /// counted from the root) on its descent, or its leaf when that is shallower.
  void transform(std::span<const Descriptor> descriptors, int direct_index_level, BowVector& bow,
                 FeatureVector& features) const;

  int branching() const { return branching_; }
  int depth() const { return depth_; }
  std::size_t node_count() const { return nodes_.size(); }
  std::size_t word_count() const { return word_nodes_.size(); }
  bool empty() const { return word_nodes_.empty(); }

  NodeId parent(NodeId node) const { return nodes_.at(node).parent; }
  int level(NodeId node) const { return nodes_.at(node).level; }
  Descriptor node_descriptor(NodeId node) const { return unpack(nodes_.at(node).descriptor); }
  std::span<const NodeId> children(NodeId node) const;
  /// Word of a leaf node, kNoWord for inner nodes.
  WordId word_of_node(NodeId node) const { return nodes_.at(node).word; }
  NodeId word_node(WordId word) const { return word_nodes_.at(word); }
  double word_weight(WordId word) const { return nodes_.at(word_nodes_.at(word)).weight; }

  /// Writes the versioned binary format of docs/BOW.md through a temporary file renamed over
  /// `path`. Throws std::runtime_error naming the file on I/O failure or an empty vocabulary.
  void save(const std::filesystem::path& path) const;
  /// Reads and validates a file written by save(); throws std::runtime_error naming the file
  /// and what was expected (magic, version, truncation, inconsistent tree).
  static Vocabulary load(const std::filesystem::path& path);

  /// Same shape, descriptors and weights (bit-exact).
  bool operator==(const Vocabulary& other) const;

 private:
  struct Node {
    NodeId parent = kNoParent;
    PackedDescriptor descriptor{};
    double weight = 0;  ///< idf for leaves, 0 for inner nodes
    int level = 0;      ///< 0 for the root
    WordId word = kNoWord;
    std::uint32_t first_child = 0;  ///< into child_ids_
    std::uint32_t child_count = 0;
  };

  /// Builds from parent links and descriptors in node order (parents before children): levels,
  /// child lists, word numbering. Throws std::runtime_error with `context` on an invalid tree.
  static Vocabulary from_nodes(int branching, int depth, std::vector<NodeId> parents,
                               std::vector<PackedDescriptor> descriptors,
                               std::vector<double> weights, const std::string& context);

  /// Leaf reached by `descriptor`; when `level_node` is given, the node at `level` on the way.
  NodeId descend(const PackedDescriptor& descriptor, int level, NodeId* level_node) const;

  int branching_ = 0;
  int depth_ = 0;
  std::vector<Node> nodes_;
  std::vector<NodeId> child_ids_;
  /// Descriptors of child_ids_, side by side so a descent reads one contiguous run per level.
  std::vector<PackedDescriptor> child_descriptors_;
  std::vector<NodeId> word_nodes_;  ///< word id -> leaf node
};

}  // namespace edx::bow
