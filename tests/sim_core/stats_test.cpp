// Statistics with hand-computed answers.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

// Samples 2 4 4 4 5 5 7 9 (n = 8, already sorted):
//   mean = 40 / 8 = 5; squared deviations 9+1+1+1+0+0+4+16 = 32
//   population SD = sqrt(32 / 8) = 2;  sample SD = sqrt(32 / 7) = 2.1380899352993950
//   RSD = 2.1380899352993950 / 5 = 0.42761798705987900
//   p50: h = 7 * 0.50 = 3.5  -> x3 + 0.5 (x4 - x3) = 4 + 0.5 * 1 = 4.5
//   p90: h = 7 * 0.90 = 6.3  -> x6 + 0.3 (x7 - x6) = 7 + 0.3 * 2 = 7.6
//   p99: h = 7 * 0.99 = 6.93 -> 7 + 0.93 * 2 = 8.86
//   p25: h = 1.75 -> 4 + 0.75 * 0 = 4
TEST(SampleSet, KnownSamples) {
  SampleSet s;
  for (double x : {5.0, 9.0, 4.0, 2.0, 4.0, 7.0, 5.0, 4.0}) s.add(x);  // unsorted input
  EXPECT_EQ(s.count(), 8u);
  EXPECT_DOUBLE_EQ(s.sum(), 40.0);
  EXPECT_DOUBLE_EQ(s.mean(), 5.0);
  EXPECT_DOUBLE_EQ(s.population_sd(), 2.0);
  EXPECT_DOUBLE_EQ(s.sd(), std::sqrt(32.0 / 7.0));
  EXPECT_NEAR(s.sd(), 2.1380899352993950, 1e-15);
  EXPECT_NEAR(s.rsd(), 0.42761798705987900, 1e-15);
  EXPECT_DOUBLE_EQ(s.min(), 2.0);
  EXPECT_DOUBLE_EQ(s.max(), 9.0);
  EXPECT_DOUBLE_EQ(s.p50(), 4.5);
  EXPECT_DOUBLE_EQ(s.p90(), 7.6);
  EXPECT_DOUBLE_EQ(s.p99(), 8.86);
  EXPECT_DOUBLE_EQ(s.percentile(25), 4.0);
  EXPECT_DOUBLE_EQ(s.percentile(0), 2.0);
  EXPECT_DOUBLE_EQ(s.percentile(100), 9.0);
  EXPECT_EQ(s.samples().front(), 5.0);  // insertion order is kept
  EXPECT_EQ(s.sorted().front(), 2.0);
}

// 1..10: h(p90) = 9 * 0.9 = 8.1 -> 9 + 0.1 * 1 = 9.1; h(p50) = 4.5 -> 5.5; sample SD =
// sqrt(82.5 / 9) = 3.0276503540974917.
TEST(SampleSet, OneToTen) {
  SampleSet s;
  for (int i = 10; i >= 1; --i) s.add(i);
  EXPECT_DOUBLE_EQ(s.mean(), 5.5);
  EXPECT_DOUBLE_EQ(s.p50(), 5.5);
  EXPECT_DOUBLE_EQ(s.p90(), 9.1);
  EXPECT_NEAR(s.sd(), 3.0276503540974917, 1e-15);
  s.add(100);  // the sorted cache is refreshed after add()
  EXPECT_DOUBLE_EQ(s.max(), 100.0);
  EXPECT_DOUBLE_EQ(s.p50(), 6.0);
}

TEST(SampleSet, UndefinedStatisticsThrow) {
  SampleSet s;
  EXPECT_THROW(s.mean(), std::domain_error);
  EXPECT_THROW(s.p50(), std::domain_error);
  s.add(3.0);
  EXPECT_DOUBLE_EQ(s.mean(), 3.0);
  EXPECT_DOUBLE_EQ(s.p99(), 3.0);
  EXPECT_DOUBLE_EQ(s.population_sd(), 0.0);
  EXPECT_THROW(s.sd(), std::domain_error);  // n - 1 = 0
  EXPECT_THROW(s.percentile(101), std::invalid_argument);
  EXPECT_THROW(s.add(std::nan("")), std::invalid_argument);
  SampleSet zero_mean;
  zero_mean.add(-1);
  zero_mean.add(1);
  EXPECT_THROW(zero_mean.rsd(), std::domain_error);
}

// Busy 1 on [0, 10), 0 on [10, 30), 1 on [30, 40): integral 20 ns, mean over 40 ns = 0.5.
// After reset at 40 and value 3 until 50: mean 3.
TEST(TimeWeighted, KnownScheduleUtilization) {
  Simulator sim;
  TimeWeighted busy(sim);
  auto schedule = [&]() -> Process {
    busy.set(1);
    co_await sim.delay(ns(10));
    busy.set(0);
    co_await sim.delay(ns(20));
    busy.add(1);
    co_await sim.delay(ns(10));
    busy.set(0);
  };
  sim.spawn(schedule());
  EXPECT_THROW(busy.mean(), std::domain_error);  // empty window
  sim.run();
  EXPECT_EQ(busy.elapsed(), ns(40));
  EXPECT_DOUBLE_EQ(busy.integral(), 20.0 * 1000);
  EXPECT_DOUBLE_EQ(busy.mean(), 0.5);
  EXPECT_DOUBLE_EQ(busy.max(), 1.0);
  busy.reset();
  busy.set(3);
  sim.run_until(ns(50));
  EXPECT_DOUBLE_EQ(busy.mean(), 3.0);
  EXPECT_DOUBLE_EQ(busy.current(), 3.0);
}

TEST(StatsRegistry, DumpsHierarchicalJsonAndListing) {
  Simulator sim;
  Counter frames;
  frames.add(41);
  ++frames;
  SampleSet latency;
  for (double x : {2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0}) latency.add(x);
  SampleSet empty;
  TimeWeighted occupancy(sim, 2.0);
  sim.run_until(ns(10));
  occupancy.set(4.0);
  sim.run_until(ns(20));  // mean (2*10 + 4*10) / 20 = 3

  StatsRegistry registry;
  registry.add("frontend.frames", frames);
  registry.add("frontend.fd.latency", latency);
  registry.add("backend.latency", empty);
  registry.add("memory.fifo.occupancy", occupancy);
  registry.add_gauge("memory.fifo.utilization", [] { return 0.25; });
  EXPECT_EQ(registry.size(), 5u);
  EXPECT_TRUE(registry.contains("frontend.fd.latency"));

  const nlohmann::json json = registry.to_json();
  EXPECT_EQ(json["frontend"]["frames"], 42);
  EXPECT_EQ(json["frontend"]["fd"]["latency"]["count"], 8);
  EXPECT_DOUBLE_EQ(json["frontend"]["fd"]["latency"]["mean"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(json["frontend"]["fd"]["latency"]["p90"].get<double>(), 7.6);
  EXPECT_DOUBLE_EQ(json["frontend"]["fd"]["latency"]["max"].get<double>(), 9.0);
  EXPECT_EQ(json["backend"]["latency"]["count"], 0);
  EXPECT_TRUE(json["backend"]["latency"]["mean"].is_null());
  EXPECT_DOUBLE_EQ(json["memory"]["fifo"]["occupancy"]["mean"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(json["memory"]["fifo"]["occupancy"]["max"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(json["memory"]["fifo"]["utilization"].get<double>(), 0.25);

  const auto listing = registry.to_listing();
  std::map<std::string, double> values(listing.begin(), listing.end());
  EXPECT_EQ(values.size(), listing.size());
  EXPECT_DOUBLE_EQ(values.at("frontend.frames"), 42.0);
  EXPECT_DOUBLE_EQ(values.at("frontend.fd.latency.p50"), 4.5);
  EXPECT_DOUBLE_EQ(values.at("frontend.fd.latency.sd"), std::sqrt(32.0 / 7.0));
  EXPECT_DOUBLE_EQ(values.at("backend.latency.count"), 0.0);
  EXPECT_EQ(values.count("backend.latency.mean"), 0u);  // undefined: left out
  EXPECT_DOUBLE_EQ(values.at("memory.fifo.occupancy.mean"), 3.0);
  EXPECT_TRUE(std::is_sorted(listing.begin(), listing.end()));

  const std::string text = registry.to_text();
  EXPECT_NE(text.find("frontend.frames 42\n"), std::string::npos);
  EXPECT_NE(text.find("frontend.fd.latency.p90 7.6\n"), std::string::npos);
}

TEST(StatsRegistry, RejectsBadAndConflictingNames) {
  Counter a;
  Counter b;
  StatsRegistry registry;
  registry.add("x.y", a);
  EXPECT_THROW(registry.add("x.y", b), std::invalid_argument);    // duplicate
  EXPECT_THROW(registry.add("x", b), std::invalid_argument);      // x is a group
  EXPECT_THROW(registry.add("x.y.z", b), std::invalid_argument);  // x.y is a leaf
  EXPECT_THROW(registry.add("", b), std::invalid_argument);
  EXPECT_THROW(registry.add("x..z", b), std::invalid_argument);
  EXPECT_THROW(registry.add("has space", b), std::invalid_argument);
  EXPECT_NO_THROW(registry.add("x.yz", b));  // a sibling sharing a prefix string is fine
  EXPECT_EQ(registry.size(), 2u);
}

}  // namespace
}  // namespace edx::sim
