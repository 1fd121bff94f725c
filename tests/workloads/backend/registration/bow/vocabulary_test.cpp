// The k-majority tree on clustered synthetic descriptors, TF-IDF weights of a hand-made corpus,
// the L1 score, and the direct index.
#include "workloads/backend/registration/bow/vocabulary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

namespace edx::bow {
namespace {

/// `clusters` random centres, `per_cluster` members each with `flips` distinct random bits
/// flipped. Returns descriptors and their cluster labels.
struct Clustered {
  std::vector<Descriptor> descriptors;
  std::vector<int> labels;
};
Clustered clustered_descriptors(int clusters, int per_cluster, int flips, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Clustered out;
  for (int c = 0; c < clusters; ++c) {
    Descriptor centre;
    for (auto& byte : centre) byte = static_cast<std::uint8_t>(rng() & 0xFF);
    for (int m = 0; m < per_cluster; ++m) {
      Descriptor d = centre;
      std::set<int> bits;
      while (static_cast<int>(bits.size()) < flips) bits.insert(static_cast<int>(rng() % 256));
      for (const int b : bits) d[b / 8] ^= static_cast<std::uint8_t>(1u << (b % 8));
      out.descriptors.push_back(d);
      out.labels.push_back(c);
    }
  }
  return out;
}

TEST(BowVocabulary, OneLevelTreePutsEachClusterInItsOwnWord) {
  // Random centres are ~128 bits apart, members at most 5 bits from theirs.
  const Clustered data = clustered_descriptors(8, 30, 5, 7);
  VocabularyOptions options;
  options.branching = 8;
  options.depth = 1;
  const Vocabulary voc = Vocabulary::create(data.descriptors, options);
  ASSERT_EQ(voc.word_count(), 8u);
  EXPECT_EQ(voc.node_count(), 9u);
  std::map<int, std::set<WordId>> words_of_cluster;
  std::map<WordId, std::set<int>> clusters_of_word;
  for (std::size_t i = 0; i < data.descriptors.size(); ++i) {
    const WordId w = voc.word_of(data.descriptors[i]);
    words_of_cluster[data.labels[i]].insert(w);
    clusters_of_word[w].insert(data.labels[i]);
  }
  for (const auto& [cluster, words] : words_of_cluster) EXPECT_EQ(words.size(), 1u) << cluster;
  for (const auto& [word, clusters] : clusters_of_word) EXPECT_EQ(clusters.size(), 1u) << word;
  EXPECT_EQ(clusters_of_word.size(), 8u);
}

TEST(BowVocabulary, DeeperTreeNeverMixesClustersInAWord) {
  const Clustered data = clustered_descriptors(12, 25, 4, 11);
  VocabularyOptions options;
  options.branching = 3;
  options.depth = 3;
  const Vocabulary voc = Vocabulary::create(data.descriptors, options);
  EXPECT_GE(voc.word_count(), 12u);
  EXPECT_LE(voc.word_count(), 27u);
  std::map<WordId, std::set<int>> clusters_of_word;
  for (std::size_t i = 0; i < data.descriptors.size(); ++i) {
    clusters_of_word[voc.word_of(data.descriptors[i])].insert(data.labels[i]);
  }
  for (const auto& [word, clusters] : clusters_of_word) EXPECT_EQ(clusters.size(), 1u) << word;
  // Tree shape: at most k children, levels 1..L, leaves are exactly the words.
  for (NodeId n = 0; n < voc.node_count(); ++n) {
    EXPECT_LE(voc.children(n).size(), 3u);
    EXPECT_LE(voc.level(n), 3);
    if (n > 0) {
      EXPECT_EQ(voc.level(n), voc.level(voc.parent(n)) + 1);
    }
    EXPECT_EQ(voc.children(n).empty() && n > 0, voc.word_of_node(n) != Vocabulary::kNoWord);
  }
}

TEST(BowVocabulary, SameSeedSameTree) {
  const Clustered data = clustered_descriptors(20, 20, 30, 3);
  VocabularyOptions options;
  options.branching = 4;
  options.depth = 3;
  options.seed = 42;
  EXPECT_TRUE(Vocabulary::create(data.descriptors, options) ==
              Vocabulary::create(data.descriptors, options));
}

TEST(BowVocabulary, IdenticalDescriptorsStopSplitting) {
  // Three distinct descriptors repeated: three words at level 1, none deeper.
  std::vector<Descriptor> set;
  for (int r = 0; r < 5; ++r) {
    for (std::uint8_t v : {0x00, 0x0F, 0xFF}) {
      Descriptor d;
      d.fill(v);
      set.push_back(d);
    }
  }
  VocabularyOptions options;
  options.branching = 4;
  options.depth = 4;
  const Vocabulary voc = Vocabulary::create(set, options);
  EXPECT_EQ(voc.word_count(), 3u);
  EXPECT_EQ(voc.node_count(), 4u);
}

TEST(BowVocabulary, RejectsBadOptionsAndNoData) {
  VocabularyOptions options;
  options.branching = 1;
  EXPECT_THROW(options.validate(), std::runtime_error);
  options = {};
  options.depth = 0;
  EXPECT_THROW(options.validate(), std::runtime_error);
  options = {};
  options.branching = 64;
  options.depth = 6;  // 2^36 words
  EXPECT_THROW(options.validate(), std::runtime_error);
  EXPECT_THROW(Vocabulary::create({}, VocabularyOptions{}), std::runtime_error);
}

/// Four descriptors pairwise >= 128 bits apart; a k = 4, L = 1 tree gives each its own word.
struct Corpus {
  Descriptor a, b, c, d;
  Vocabulary voc;
  Corpus() {
    a.fill(0x00);
    b.fill(0xFF);
    c.fill(0x0F);
    d.fill(0xF0);
    VocabularyOptions options;
    options.branching = 4;
    options.depth = 1;
    const std::vector<Descriptor> all = {a, b, c, d};
    voc = Vocabulary::create(all, options);
  }
};

TEST(BowVocabulary, TfIdfOfHandMadeCorpus) {
  Corpus corpus;
  Vocabulary& voc = corpus.voc;
  ASSERT_EQ(voc.word_count(), 4u);
  const WordId wa = voc.word_of(corpus.a), wb = voc.word_of(corpus.b), wc = voc.word_of(corpus.c),
               wd = voc.word_of(corpus.d);
  EXPECT_EQ((std::set<WordId>{wa, wb, wc, wd}).size(), 4u);
  // N = 4 images; a in 3 of them, b in 2, c and d in 1.
  const std::vector<std::vector<Descriptor>> images = {
      {corpus.a, corpus.a, corpus.b}, {corpus.a, corpus.c}, {corpus.a, corpus.d}, {corpus.b}};
  const std::vector<std::size_t> n = voc.set_idf(images);
  EXPECT_EQ(n[wa], 3u);
  EXPECT_EQ(n[wb], 2u);
  EXPECT_EQ(n[wc], 1u);
  EXPECT_EQ(n[wd], 1u);
  EXPECT_NEAR(voc.word_weight(wa), 0.28768207245178085, 1e-12);  // ln(4/3)
  EXPECT_NEAR(voc.word_weight(wb), 0.6931471805599453, 1e-12);   // ln 2
  EXPECT_NEAR(voc.word_weight(wc), 1.3862943611198906, 1e-12);   // ln 4
  EXPECT_NEAR(voc.word_weight(wd), 1.3862943611198906, 1e-12);
  // Image 0: tf(a) = 2/3, tf(b) = 1/3; v = (2/3 ln(4/3), 1/3 ln 2) / |.|_1.
  const BowVector v = voc.transform(images[0]);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_NEAR(v.at(wa), 0.453574306633271, 1e-12);
  EXPECT_NEAR(v.at(wb), 0.5464256933667291, 1e-12);
  // Image 1: (1/2 ln(4/3), 1/2 ln 4) -> ln(4/3) / ln(16/3), ln 4 / ln(16/3).
  const BowVector v1 = voc.transform(images[1]);
  EXPECT_NEAR(v1.at(wa), 0.28768207245178085 / 1.6739764335716716, 1e-12);
  EXPECT_NEAR(v1.at(wc), 1.3862943611198906 / 1.6739764335716716, 1e-12);
}

TEST(BowVocabulary, WordInEveryImageHasZeroWeightAndIsLeftOut) {
  Corpus corpus;
  const std::vector<std::vector<Descriptor>> images = {{corpus.a, corpus.b}, {corpus.a}};
  const std::vector<std::size_t> n = corpus.voc.set_idf(images);
  const WordId wa = corpus.voc.word_of(corpus.a), wb = corpus.voc.word_of(corpus.b),
               wc = corpus.voc.word_of(corpus.c);
  EXPECT_EQ(corpus.voc.word_weight(wa), 0.0);  // ln(2/2)
  EXPECT_NEAR(corpus.voc.word_weight(wb), std::log(2.0), 1e-12);
  EXPECT_EQ(n[wc], 0u);
  EXPECT_EQ(corpus.voc.word_weight(wc), 0.0);  // unseen: 0, as DBoW2
  const BowVector v = corpus.voc.transform(images[0]);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_DOUBLE_EQ(v.at(wb), 1.0);
  EXPECT_TRUE(corpus.voc.transform(images[1]).empty());
}

TEST(BowScore, IdenticalVectorsScoreOneDisjointZero) {
  const BowVector v = {{1, 0.5}, {2, 0.3}, {7, 0.2}};
  EXPECT_DOUBLE_EQ(l1_score(v, v), 1.0);
  // Same direction, different scale: 1.
  const BowVector scaled = {{1, 1.5}, {2, 0.9}, {7, 0.6}};
  EXPECT_NEAR(l1_score(v, scaled), 1.0, 1e-15);
  EXPECT_DOUBLE_EQ(l1_score(v, {{3, 0.4}, {4, 0.6}}), 0.0);
  EXPECT_DOUBLE_EQ(l1_score(v, {}), 0.0);
}

TEST(BowScore, PartialOverlapByHand) {
  // |v - w|_1 = 0.5 + 0 + 0.5 = 1 -> s = 1 - 0.5 = 0.5.
  EXPECT_DOUBLE_EQ(l1_score({{1, 0.5}, {2, 0.5}}, {{2, 0.5}, {3, 0.5}}), 0.5);
  // v = (0.6, 0.4, 0), w = (0.2, 0, 0.8): |v - w|_1 = 0.4 + 0.4 + 0.8 = 1.6 -> s = 0.2.
  EXPECT_NEAR(l1_score({{1, 0.6}, {2, 0.4}}, {{1, 0.2}, {3, 0.8}}), 0.2, 1e-15);
  // Unnormalised input is normalised first: (3, 2) ~ (0.6, 0.4).
  EXPECT_NEAR(l1_score({{1, 3.0}, {2, 2.0}}, {{1, 0.2}, {3, 0.8}}), 0.2, 1e-15);
}

TEST(BowVocabulary, DirectIndexGroupsFeaturesByAncestorNode) {
  const Clustered data = clustered_descriptors(9, 10, 20, 5);
  VocabularyOptions options;
  options.branching = 3;
  options.depth = 3;
  const Vocabulary voc = Vocabulary::create(data.descriptors, options);
  BowVector bow;
  FeatureVector features;
  voc.transform(data.descriptors, 1, bow, features);
  std::size_t listed = 0;
  for (const auto& [node, indices] : features) {
    EXPECT_EQ(voc.level(node), 1);
    for (const std::uint32_t i : indices) {
      // The node is the level-1 ancestor of the feature's word.
      NodeId n = voc.word_node(voc.word_of(data.descriptors[i]));
      while (voc.level(n) > 1) n = voc.parent(n);
      EXPECT_EQ(n, node) << "feature " << i;
      ++listed;
    }
  }
  EXPECT_EQ(listed, data.descriptors.size());
  EXPECT_THROW(voc.transform(data.descriptors, 4, bow, features), std::runtime_error);
  EXPECT_NEAR(l1_norm(bow), 1.0, 1e-12);
}

}  // namespace
}  // namespace edx::bow
