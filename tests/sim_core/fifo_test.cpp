// Bounded FIFOs: back-pressure timing, a hand-computed tandem pipeline, occupancy statistics.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

// Capacity 2. The producer puts items 0..4 as fast as possible; the consumer takes one every
// 10 ns starting at 10 ns. Puts 0 and 1 complete at 0; put 2 waits until the get at 10 frees a
// slot, put 3 until 20, put 4 until 30. Items arrive at 10, 20, 30, 40, 50.
// Occupancy: 2 on [0, 40) (each get admits a blocked item at once until 30, the get at 30
// admits item 4), 1 on [40, 50), 0 at 50 -> integral 2*40 + 1*10 = 90 item*ns, mean 1.8.
TEST(Fifo, BackPressureStallsTheProducerUntilASlotFrees) {
  Simulator sim;
  Fifo<int> fifo(sim, 2, "link");
  std::vector<Time> put_done;
  std::vector<std::pair<int, Time>> received;
  auto producer = [&]() -> Process {
    for (int i = 0; i < 5; ++i) {
      co_await fifo.put(i);
      put_done.push_back(sim.now());
    }
  };
  auto consumer = [&]() -> Process {
    for (int i = 0; i < 5; ++i) {
      co_await sim.delay(ns(10));
      const int item = co_await fifo.get();
      received.emplace_back(item, sim.now());
    }
  };
  sim.spawn(producer(), "producer");
  sim.spawn(consumer(), "consumer");
  sim.run();
  EXPECT_EQ(put_done, (std::vector<Time>{0, 0, ns(10), ns(20), ns(30)}));
  const std::vector<std::pair<int, Time>> expected = {
      {0, ns(10)}, {1, ns(20)}, {2, ns(30)}, {3, ns(40)}, {4, ns(50)}};
  EXPECT_EQ(received, expected);
  EXPECT_EQ(fifo.puts(), 5u);
  EXPECT_EQ(fifo.gets(), 5u);
  EXPECT_TRUE(fifo.empty());
  EXPECT_DOUBLE_EQ(fifo.occupancy().integral(), 90.0 * 1000);
  EXPECT_DOUBLE_EQ(fifo.occupancy().mean(), 1.8);
  EXPECT_DOUBLE_EQ(fifo.occupancy().max(), 2.0);
}

TEST(Fifo, GetWaitsWhileEmptyAndPutHandsOverDirectly) {
  Simulator sim;
  Fifo<std::string> fifo(sim, 1, "mailbox");
  std::vector<std::pair<std::string, Time>> received;
  auto consumer = [&]() -> Process {
    for (int i = 0; i < 2; ++i) {
      std::string message = co_await fifo.get();
      received.emplace_back(std::move(message), sim.now());
    }
  };
  auto producer = [&]() -> Process {
    co_await sim.delay(ns(3));
    co_await fifo.put("hello");
    EXPECT_EQ(fifo.size(), 0u);  // went straight to the waiting consumer
    co_await sim.delay(ns(4));
    co_await fifo.put("world");
  };
  sim.spawn(consumer());
  sim.spawn(producer());
  sim.run();
  const std::vector<std::pair<std::string, Time>> expected = {{"hello", ns(3)}, {"world", ns(7)}};
  EXPECT_EQ(received, expected);
  EXPECT_DOUBLE_EQ(fifo.occupancy().max(), 0.0);
}

TEST(Fifo, MoveOnlyItemsAndNonBlockingCalls) {
  Simulator sim;
  Fifo<std::unique_ptr<int>> fifo(sim, 1, "owned");
  auto item = std::make_unique<int>(42);
  EXPECT_TRUE(fifo.try_put(item));
  EXPECT_EQ(item, nullptr);  // moved into the FIFO
  auto second = std::make_unique<int>(7);
  EXPECT_FALSE(fifo.try_put(second));  // full: untouched
  ASSERT_NE(second, nullptr);
  std::optional<std::unique_ptr<int>> out = fifo.try_get();
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(**out, 42);
  EXPECT_FALSE(fifo.try_get().has_value());
  EXPECT_THROW(Fifo<int>(sim, 0, "none"), std::invalid_argument);
}

// Tandem pipeline: stage 1 (2 ns) -> FIFO(1) -> stage 2 (3 ns) -> FIFO(1) -> stage 3 (6 ns),
// 5 jobs available to stage 1 at t=0. A stage gets a job, serves it, then puts it downstream,
// blocking while the FIFO is full (blocking after service). With g = get time, p = put done:
//   g1(j) = p1(j-1)                  p1(j) = max(g1(j) + 2, g2(j-1))
//   g2(j) = max(p1(j), p2(j-1))      p2(j) = max(g2(j) + 3, g3(j-1))
//   g3(j) = max(p2(j), done(j-1))    done(j) = g3(j) + 6
// j=0: g1 0  p1 2  | g2 2  p2 5   | g3 5  done 11
// j=1: g1 2  p1 4  | g2 5  p2 8   | g3 11 done 17
// j=2: g1 4  p1 6  | g2 8  p2 11  | g3 17 done 23
// j=3: g1 6  p1 8  | g2 11 p2 17  | g3 23 done 29
// j=4: g1 8  p1 11 | g2 17 p2 23  | g3 29 done 35
// Stage 3 is the bottleneck: stage 2 stalls on its put from job 3 on, stage 1 on job 4.
TEST(Fifo, TandemPipelineMatchesHandComputedTimes) {
  Simulator sim;
  Fifo<int> first(sim, 1, "s1_s2");
  Fifo<int> second(sim, 1, "s2_s3");
  std::vector<Time> stage1_put;
  std::vector<Time> stage2_get;
  std::vector<Time> stage2_put;
  std::vector<Time> stage3_get;
  std::vector<std::pair<int, Time>> done;
  constexpr int kJobs = 5;
  auto stage1 = [&]() -> Process {
    for (int job = 0; job < kJobs; ++job) {
      co_await sim.delay(ns(2));
      co_await first.put(job);
      stage1_put.push_back(sim.now());
    }
  };
  auto stage2 = [&]() -> Process {
    for (int i = 0; i < kJobs; ++i) {
      const int job = co_await first.get();
      stage2_get.push_back(sim.now());
      co_await sim.delay(ns(3));
      co_await second.put(job);
      stage2_put.push_back(sim.now());
    }
  };
  auto stage3 = [&]() -> Process {
    for (int i = 0; i < kJobs; ++i) {
      const int job = co_await second.get();
      stage3_get.push_back(sim.now());
      co_await sim.delay(ns(6));
      done.emplace_back(job, sim.now());
    }
  };
  sim.spawn(stage1(), "stage1");
  sim.spawn(stage2(), "stage2");
  sim.spawn(stage3(), "stage3");
  sim.run();
  const auto in_ns = [](std::vector<Time> times) {
    for (Time& t : times) t /= 1000;
    return times;
  };
  EXPECT_EQ(in_ns(stage1_put), (std::vector<Time>{2, 4, 6, 8, 11}));
  EXPECT_EQ(in_ns(stage2_get), (std::vector<Time>{2, 5, 8, 11, 17}));
  EXPECT_EQ(in_ns(stage2_put), (std::vector<Time>{5, 8, 11, 17, 23}));
  EXPECT_EQ(in_ns(stage3_get), (std::vector<Time>{5, 11, 17, 23, 29}));
  const std::vector<std::pair<int, Time>> expected = {
      {0, ns(11)}, {1, ns(17)}, {2, ns(23)}, {3, ns(29)}, {4, ns(35)}};
  EXPECT_EQ(done, expected);
  EXPECT_EQ(sim.now(), ns(35));
}

}  // namespace
}  // namespace edx::sim
