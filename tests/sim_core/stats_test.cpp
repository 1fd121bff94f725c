// Statistics with hand-computed answers.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

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

TEST(TimeWeighted, SetAtAPastTimeGivesTheSameIntegralAsSetThen) {
  // 1 over [10, 30) ns and 2 over [40, 50): integral 20 + 20 = 40 ns at 50 ns, max 2.
  Simulator sim;
  TimeWeighted live(sim), later(sim);
  auto schedule = [&]() -> Process {
    co_await sim.delay(ns(10));
    live.set(1);
    co_await sim.delay(ns(20));
    live.set(0);
    co_await sim.delay(ns(10));
    live.set(2);
    co_await sim.delay(ns(10));
    live.set(0);
    // The same changes booked afterwards.
    later.set_at(ns(10), 1);
    later.set_at(ns(30), 0);
    later.set_at(ns(40), 2);
    later.set_at(ns(50), 0);
  };
  sim.spawn(schedule());
  sim.run_until(ns(60));
  EXPECT_DOUBLE_EQ(live.integral(), 40.0 * 1000);
  EXPECT_EQ(later.integral(), live.integral());
  EXPECT_EQ(later.max(), 2.0);
  EXPECT_EQ(later.last_change(), ns(50));
  // Before the last change, or after now: refused.
  EXPECT_THROW(later.set_at(ns(49), 1), std::logic_error);
  EXPECT_THROW(later.set_at(ns(61), 1), std::logic_error);
  EXPECT_EQ(later.integral(), live.integral());
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
