// The pending-event queue against a straightforward reference (an ordered std::set), in plain
// heap mode and with the timing wheel, under several delay distributions.
#include "sim_core/event_queue.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <tuple>

namespace edx::sim {
namespace {

using Key = std::tuple<Time, std::uint64_t, void*>;

Key key_of(const QueueEntry& entry) { return {entry.time, entry.order, entry.target}; }

TEST(EventQueue, PackOrderSortsByPriorityThenSequence) {
  EXPECT_LT(pack_order(-5, 100), pack_order(0, 1));
  EXPECT_LT(pack_order(0, 1), pack_order(0, 2));
  EXPECT_LT(pack_order(0, 999), pack_order(1, 0));
  const QueueEntry entry{10, pack_order(-3, 42), nullptr};
  EXPECT_EQ(entry.priority(), -3);
  EXPECT_EQ(entry.sequence(), 42u);
}

struct Scenario {
  std::string name;
  EventQueue::Tuning tuning;
  std::function<Time(std::mt19937_64&)> delay;  ///< delay of a newly scheduled entry
  std::size_t target_size;                      ///< pending entries the workload hovers around
};

// A hold-model workload (pop the earliest, schedule successors) with phases of growth and
// shrinkage and occasional removals, compared entry by entry with an ordered set.
void run_against_reference(const Scenario& scenario, bool* saw_wheel) {
  std::mt19937_64 random(99);
  EventQueue queue(scenario.tuning);
  std::set<Key> reference;
  std::uint64_t sequence = 0;
  Time now = 0;
  const auto push = [&](Time when) {
    const auto priority = static_cast<Priority>(static_cast<int>(random() % 5) - 2);
    auto* target = reinterpret_cast<void*>((sequence + 1) * 16);  // identity only
    const QueueEntry entry{when, pack_order(priority, sequence++), target};
    queue.push(entry);
    reference.insert(key_of(entry));
  };
  for (int step = 0; step < 60'000; ++step) {
    // Phase: grow to 2x target, shrink to a handful, grow again ...
    const bool shrinking = (step / 15'000) % 2 == 1;
    const std::size_t want = shrinking ? 2 : 2 * scenario.target_size;
    QueueEntry top{};
    if (queue.empty() || (reference.size() < want && random() % 3 != 0)) {
      push(now + scenario.delay(random));
    } else {
      ASSERT_TRUE(queue.pop_not_after(kTimeMax - 1, top));
      ASSERT_EQ(key_of(top), *reference.begin()) << scenario.name << " step " << step;
      reference.erase(reference.begin());
      now = top.time;
      if (!shrinking) push(now + scenario.delay(random));
      if (random() % 8 == 0) push(now);  // same-time wake-ups
    }
    if (step % 5000 == 4999) {
      const std::size_t removed =
          queue.remove_if([](const QueueEntry& entry) { return entry.sequence() % 11 == 3; });
      std::size_t expected = 0;
      for (auto it = reference.begin(); it != reference.end();) {
        if ((std::get<1>(*it) & ((std::uint64_t{1} << 48) - 1)) % 11 == 3) {
          it = reference.erase(it);
          ++expected;
        } else {
          ++it;
        }
      }
      ASSERT_EQ(removed, expected) << scenario.name;
    }
    ASSERT_EQ(queue.size(), reference.size()) << scenario.name;
    if (queue.wheel_active()) *saw_wheel = true;
  }
  // A limit before the earliest entry pops nothing.
  QueueEntry top{};
  if (!reference.empty() && std::get<0>(*reference.begin()) > 0) {
    EXPECT_FALSE(queue.pop_not_after(std::get<0>(*reference.begin()) - 1, top));
  }
  while (queue.pop_not_after(kTimeMax - 1, top)) {
    ASSERT_EQ(key_of(top), *reference.begin()) << scenario.name;
    reference.erase(reference.begin());
  }
  EXPECT_TRUE(reference.empty()) << scenario.name;
}

TEST(EventQueue, MatchesReferenceInEveryMode) {
  const EventQueue::Tuning small{
      .activate_size = 16, .deactivate_size = 8, .max_wheel_bits = 4, .min_eval_interval = 64};
  const EventQueue::Tuning medium{
      .activate_size = 64, .deactivate_size = 16, .max_wheel_bits = 7, .min_eval_interval = 256};
  const std::vector<Scenario> scenarios = {
      {"uniform ns, small wheel", small, [](std::mt19937_64& r) { return (1 + r() % 1000) * 1000; },
       200},
      {"many ties", small, [](std::mt19937_64& r) { return (r() % 4) * 1000; }, 100},
      {"tiny delays", medium, [](std::mt19937_64& r) { return r() % 3; }, 300},
      {"bimodal ns and ms", medium,
       [](std::mt19937_64& r) { return r() % 10 == 0 ? 1'000'000'000 + r() % 1000 : r() % 5000; },
       300},
      {"log-uniform 1 ps .. 1 s", small, [](std::mt19937_64& r) { return Time{1} << (r() % 40); },
       150},
      {"huge delays", small, [](std::mt19937_64& r) { return (r() % 1000) << 50; }, 100},
      {"default tuning", EventQueue::Tuning{}, [](std::mt19937_64& r) { return 1 + r() % 100'000; },
       2000},
  };
  for (const Scenario& scenario : scenarios) {
    bool saw_wheel = false;
    run_against_reference(scenario, &saw_wheel);
    EXPECT_TRUE(saw_wheel) << scenario.name << ": the wheel was never used";
  }
}

TEST(EventQueue, WheelSwitchesOnForLargeAndOffForSmallQueues) {
  EventQueue queue;  // default tuning: wheel from 16 pending entries, off below 8
  for (std::uint64_t i = 0; i < 10'000; ++i) {
    queue.push({i % 17, pack_order(0, i), reinterpret_cast<void*>(16)});
  }
  EXPECT_TRUE(queue.wheel_active());
  QueueEntry top{};
  Time last = 0;
  while (queue.size() > 5 && queue.pop_not_after(kTimeMax - 1, top)) {
    ASSERT_GE(top.time, last);
    last = top.time;
  }
  for (std::uint64_t i = 0; i < 20'000; ++i) {  // hold around 5 pending entries
    queue.push({top.time + i % 5, pack_order(0, 10'000 + i), reinterpret_cast<void*>(16)});
    ASSERT_TRUE(queue.pop_not_after(kTimeMax - 1, top));
    ASSERT_GE(top.time, last);
    last = top.time;
  }
  EXPECT_FALSE(queue.wheel_active());
  EXPECT_EQ(queue.size(), 5u);
}

}  // namespace
}  // namespace edx::sim
