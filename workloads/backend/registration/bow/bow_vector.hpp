#pragma once
// Bag-of-words vectors (Galvez-Lopez and Tardos 2012, DBoW2): an image as a sparse vector of
// word weights, and its direct index (the features grouped by vocabulary node, used to restrict
// descriptor matching to features under the same node).
#include <cstdint>
#include <map>
#include <vector>

namespace edx::bow {

using WordId = std::uint32_t;
using NodeId = std::uint32_t;

/// Sparse word -> weight vector of one image (TF-IDF, L1-normalised by Vocabulary::transform).
using BowVector = std::map<WordId, double>;

/// Direct index of one image: vocabulary node (at the chosen level) -> indices of the image's
/// features whose descriptor descends through that node, in increasing order.
using FeatureVector = std::map<NodeId, std::vector<std::uint32_t>>;

/// |v|_1 = sum_i |v_i|.
double l1_norm(const BowVector& v);

/// v / |v|_1 (unchanged when |v|_1 = 0).
BowVector l1_normalized(const BowVector& v);

/// DBoW2's L1 score of two vectors, s = 1 - 0.5 * | v/|v|_1 - w/|w|_1 |_1, in [0, 1]: 1 for
/// vectors of the same direction, 0 for vectors without a common word (or an empty one).
/// Computed over the common words only, since for unit L1 vectors
///   1 - 0.5 |v - w|_1 = 0.5 * sum_{i: v_i != 0, w_i != 0} (|v_i| + |w_i| - |v_i - w_i|).
double l1_score(const BowVector& v, const BowVector& w);

}  // namespace edx::bow
