#include "workloads/backend/registration/bow/database.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edx::bow {

ImageId Database::add(const BowVector& bow, FeatureVector features) {
  if (images_.size() >= 0xFFFFFFFFu) throw std::runtime_error("BoW database: too many images");
  const auto id = static_cast<ImageId>(images_.size());
  Image image{l1_normalized(bow), std::move(features)};
  for (const auto& [word, weight] : image.bow) {
    if (word >= inverse_index_.size()) inverse_index_.resize(static_cast<std::size_t>(word) + 1);
    inverse_index_[word].push_back({id, weight});
  }
  images_.push_back(std::move(image));
  return id;
}

const std::vector<Database::Posting>& Database::postings(WordId word) const {
  static const std::vector<Posting> kNone;
  return word < inverse_index_.size() ? inverse_index_[word] : kNone;
}

std::vector<QueryResult> Database::query(const BowVector& bow, std::size_t max_results,
                                         QueryStats* stats) const {
  QueryStats counts;
  const BowVector q = l1_normalized(bow);
  std::vector<double> accumulated(images_.size(), 0.0);
  std::vector<bool> touched(images_.size(), false);
  for (const auto& [word, qi] : q) {
    ++counts.words;
    for (const Posting& p : postings(word)) {
      accumulated[p.image] += std::abs(qi) + std::abs(p.weight) - std::abs(qi - p.weight);
      touched[p.image] = true;
      ++counts.postings;
    }
  }
  std::vector<QueryResult> results;
  for (ImageId id = 0; id < images_.size(); ++id) {
    if (touched[id]) results.push_back({id, std::clamp(0.5 * accumulated[id], 0.0, 1.0)});
  }
  counts.candidates = results.size();
  auto better = [](const QueryResult& a, const QueryResult& b) {
    return a.score != b.score ? a.score > b.score : a.image < b.image;
  };
  if (max_results > 0 && max_results < results.size()) {
    std::partial_sort(results.begin(), results.begin() + static_cast<std::ptrdiff_t>(max_results),
                      results.end(), better);
    results.resize(max_results);
  } else {
    std::sort(results.begin(), results.end(), better);
  }
  if (stats) *stats = counts;
  return results;
}

}  // namespace edx::bow
