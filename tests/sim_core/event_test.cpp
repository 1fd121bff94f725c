// Events: immediate and timed notification, any_of / all_of.
#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

TEST(Event, NotifyWakesCurrentWaitersInOrder) {
  Simulator sim;
  Event ready(sim, "ready");
  std::vector<std::pair<std::string, Time>> woken;
  auto waiter = [&](std::string name) -> Process {
    co_await ready;
    woken.emplace_back(name, sim.now());
  };
  auto notifier = [&]() -> Process {
    co_await sim.delay(ns(4));
    EXPECT_EQ(ready.waiting(), 2u);
    ready.notify();
    EXPECT_EQ(ready.waiting(), 0u);
    EXPECT_TRUE(woken.empty());  // waiters resume later in this instant, not inside notify()
  };
  sim.spawn(waiter("first"));
  sim.spawn(waiter("second"));
  sim.spawn(notifier());
  sim.run();
  const std::vector<std::pair<std::string, Time>> expected = {{"first", ns(4)}, {"second", ns(4)}};
  EXPECT_EQ(woken, expected);
  EXPECT_EQ(ready.notifications(), 1u);
}

TEST(Event, NotificationWithoutWaitersIsLost) {
  Simulator sim;
  Event ping(sim, "ping");
  Time woke = 0;
  auto late_waiter = [&]() -> Process {
    co_await sim.delay(ns(2));
    co_await ping;  // the notification at 1 ns happened before: waits for the one at 6 ns
    woke = sim.now();
  };
  sim.spawn(late_waiter());
  ping.notify_at(ns(1));
  ping.notify_at(ns(6));
  EXPECT_EQ(ping.pending_notifications(), 2u);
  sim.run();
  EXPECT_EQ(woke, ns(6));
  EXPECT_EQ(ping.notifications(), 2u);
  EXPECT_EQ(ping.pending_notifications(), 0u);
}

TEST(Event, TimedNotificationAppearsInTheLog) {
  Simulator sim;
  sim.enable_event_log();
  Event tick(sim, "tick");
  auto waiter = [&]() -> Process { co_await tick; };
  sim.spawn(waiter(), "w");
  tick.notify_after(ns(3), -2);
  sim.run();
  const std::vector<EventRecord>& log = sim.event_log();
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[1].kind, EventRecord::Kind::kNotify);
  EXPECT_EQ(log[1].name, "tick");
  EXPECT_EQ(log[1].time, ns(3));
  EXPECT_EQ(log[2].name, "w");
  EXPECT_EQ(log[2].priority, -2);  // woken with the notification's priority
}

TEST(Event, DestroyingAnEventCancelsItsTimedNotifications) {
  Simulator sim;
  auto doomed = std::make_unique<Event>(sim, "doomed");
  doomed->notify_at(ns(5));
  doomed->notify_at(ns(9));
  Event kept(sim, "kept");
  kept.notify_at(ns(7));
  EXPECT_EQ(sim.pending_events(), 3u);
  doomed.reset();
  EXPECT_EQ(sim.pending_events(), 1u);
  sim.run();
  EXPECT_EQ(sim.now(), ns(7));
  EXPECT_THROW(kept.notify_at(ns(1)), std::invalid_argument);
}

TEST(Event, AnyOfYieldsTheFirstEventAndUnlinksTheOthers) {
  Simulator sim;
  Event a(sim, "a");
  Event b(sim, "b");
  Event c(sim, "c");
  std::size_t index = 99;
  Time woke = 0;
  auto waiter = [&]() -> Process {
    index = co_await sim.any_of({a, b, c});
    woke = sim.now();
  };
  sim.spawn(waiter());
  b.notify_at(ns(5));
  a.notify_at(ns(8));
  sim.run_until(ns(1));
  EXPECT_EQ(a.waiting(), 1u);
  EXPECT_EQ(b.waiting(), 1u);
  sim.run();
  EXPECT_EQ(index, 1u);
  EXPECT_EQ(woke, ns(5));
  EXPECT_EQ(a.waiting(), 0u);  // unlinked when b fired
  EXPECT_EQ(c.waiting(), 0u);
}

TEST(Event, AnyOfWithSameTimeNotificationsTakesTheEarlierQueued) {
  Simulator sim;
  Event a(sim, "a");
  Event b(sim, "b");
  std::size_t index = 99;
  const std::vector<Event*> both = {&a, &b};
  auto waiter = [&]() -> Process { index = co_await sim.any_of(both); };
  sim.spawn(waiter());
  a.notify_at(ns(5), 1);
  b.notify_at(ns(5), 0);  // same time, smaller priority number: fires first
  sim.run();
  EXPECT_EQ(index, 1u);
}

TEST(Event, AllOfWaitsForEveryEvent) {
  Simulator sim;
  Event a(sim, "a");
  Event b(sim, "b");
  Event c(sim, "c");
  Time woke = 0;
  auto waiter = [&]() -> Process {
    co_await sim.all_of({a, b, c});
    woke = sim.now();
  };
  auto notifier = [&]() -> Process {
    co_await sim.delay(ns(3));
    b.notify();
    co_await sim.delay(ns(3));
    b.notify();  // a repeat does not count twice
    a.notify();
    co_await sim.delay(ns(6));
    c.notify();
  };
  sim.spawn(waiter());
  sim.spawn(notifier());
  sim.run();
  EXPECT_EQ(woke, ns(12));
}

TEST(Event, AllOfEmptyIsReadyAndAnyOfEmptyThrows) {
  Simulator sim;
  Time woke = 1;
  auto waiter = [&]() -> Process {
    co_await sim.all_of({});
    woke = sim.now();
  };
  sim.spawn(waiter());
  sim.run();
  EXPECT_EQ(woke, 0u);
  EXPECT_THROW(sim.any_of({}), std::invalid_argument);
}

TEST(Event, WaitingAgainAfterWakeWaitsForTheNextNotification) {
  Simulator sim;
  Event tick(sim, "tick");
  std::vector<Time> wakes;
  auto waiter = [&]() -> Process {
    for (int i = 0; i < 3; ++i) {
      co_await tick;
      wakes.push_back(sim.now());
    }
  };
  sim.spawn(waiter());
  for (Time t : {ns(1), ns(2), ns(3), ns(4)}) tick.notify_at(t);
  sim.run();
  EXPECT_EQ(wakes, (std::vector<Time>{ns(1), ns(2), ns(3)}));
}

}  // namespace
}  // namespace edx::sim
