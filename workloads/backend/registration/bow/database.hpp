#pragma once
// An image database for place recognition (DBoW2's TemplatedDatabase with an inverse index):
// each added image's L1-normalised BoW vector is kept, and every word lists the images that
// contain it with their weight. A query scores only the images sharing a word with it, with the
// L1 score accumulated over the common words (bow_vector.hpp):
//   s(q, d) = 0.5 * sum_{i in q, i in d} (|q_i| + |d_i| - |q_i - d_i|).
#include <cstdint>
#include <vector>

#include "workloads/backend/registration/bow/bow_vector.hpp"

namespace edx::bow {

using ImageId = std::uint32_t;

struct QueryResult {
  ImageId image = 0;
  double score = 0;  ///< L1 score in [0, 1]
};

/// Work counts of one query (for the trace's "BoW query" kernel).
struct QueryStats {
  std::size_t words = 0;       ///< words of the query looked up in the inverse index
  std::size_t postings = 0;    ///< inverse-index entries visited (one score update each)
  std::size_t candidates = 0;  ///< images sharing at least one word with the query
};

class Database {
 public:
  struct Posting {
    ImageId image = 0;
    double weight = 0;  ///< the word's weight in the image's normalised vector
  };

  /// Adds an image (its vector is L1-normalised here); ids count up from 0. The direct index
  /// is kept for matching against the image later.
  ImageId add(const BowVector& bow, FeatureVector features = {});

  /// Images sharing a word with `bow`, by decreasing score (ties: lower id first), at most
  /// max_results of them (0: all).
  std::vector<QueryResult> query(const BowVector& bow, std::size_t max_results,
                                 QueryStats* stats = nullptr) const;

  std::size_t size() const { return images_.size(); }
  const BowVector& bow(ImageId image) const { return images_.at(image).bow; }
  const FeatureVector& features(ImageId image) const { return images_.at(image).features; }
  /// The inverse-index entries of a word, in image order (empty for unseen words).
  const std::vector<Posting>& postings(WordId word) const;

 private:
  struct Image {
    BowVector bow;
    FeatureVector features;
  };
  std::vector<Image> images_;
  std::vector<std::vector<Posting>> inverse_index_;  ///< by word id
};

}  // namespace edx::bow
