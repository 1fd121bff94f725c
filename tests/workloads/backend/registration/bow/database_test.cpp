// The inverse-index database: scores equal to l1_score, ranking, limits, work counts.
#include "workloads/backend/registration/bow/database.hpp"

#include <gtest/gtest.h>

namespace edx::bow {
namespace {

TEST(BowDatabase, RanksByL1ScoreThroughTheInverseIndex) {
  Database db;
  const BowVector a = {{1, 0.6}, {2, 0.4}};
  const BowVector b = {{1, 0.2}, {3, 0.8}};
  const BowVector c = {{4, 2.0}, {5, 2.0}};  // unnormalised: stored as 0.5, 0.5
  EXPECT_EQ(db.add(a), 0u);
  EXPECT_EQ(db.add(b), 1u);
  EXPECT_EQ(db.add(c), 2u);
  EXPECT_EQ(db.size(), 3u);
  ASSERT_EQ(db.postings(1).size(), 2u);
  EXPECT_EQ(db.postings(1)[1].image, 1u);
  EXPECT_DOUBLE_EQ(db.postings(4)[0].weight, 0.5);
  EXPECT_TRUE(db.postings(99).empty());

  // Query (0.6, 0.4) on words 1, 2: image 0 identical (1), image 1 s = 0.2 (by hand:
  // |q - b|_1 = 0.4 + 0.4 + 0.8 = 1.6), image 2 shares no word (not returned).
  QueryStats stats;
  const std::vector<QueryResult> results = db.query({{1, 3.0}, {2, 2.0}}, 0, &stats);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].image, 0u);
  EXPECT_NEAR(results[0].score, 1.0, 1e-15);
  EXPECT_EQ(results[1].image, 1u);
  EXPECT_NEAR(results[1].score, 0.2, 1e-15);
  EXPECT_NEAR(results[1].score, l1_score(a, b), 1e-15);
  EXPECT_EQ(stats.words, 2u);
  EXPECT_EQ(stats.postings, 3u);  // word 1: images 0, 1; word 2: image 0
  EXPECT_EQ(stats.candidates, 2u);

  const std::vector<QueryResult> top = db.query(a, 1);
  ASSERT_EQ(top.size(), 1u);
  EXPECT_EQ(top[0].image, 0u);
  EXPECT_TRUE(db.query({{9, 1.0}}, 5).empty());
}

TEST(BowDatabase, EqualScoresKeepImageOrder) {
  Database db;
  db.add({{1, 1.0}});
  db.add({{2, 1.0}});
  db.add({{1, 1.0}});
  const auto results = db.query({{1, 0.5}, {2, 0.5}}, 0);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].image, 0u);
  EXPECT_EQ(results[1].image, 1u);
  EXPECT_EQ(results[2].image, 2u);
  EXPECT_DOUBLE_EQ(results[0].score, 0.5);
}

TEST(BowDatabase, KeepsDirectIndex) {
  Database db;
  const ImageId id = db.add({{1, 1.0}}, {{7, {0, 2}}});
  EXPECT_EQ(db.features(id).at(7), (std::vector<std::uint32_t>{0, 2}));
}

}  // namespace
}  // namespace edx::bow
