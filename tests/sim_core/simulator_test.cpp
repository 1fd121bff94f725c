// Simulator core: time advance, event order, processes, joins, exceptions, teardown,
// determinism.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

using Trace = std::vector<std::pair<std::string, Time>>;

Process wait_and_log(Simulator& sim, Trace& trace, std::string name, Time delay,
                     Priority priority) {
  co_await sim.delay(delay, priority);
  trace.emplace_back(name, sim.now());
}

TEST(Simulator, DelaysAdvanceTimeAndCountEvents) {
  Simulator sim;
  std::vector<Time> seen;
  auto body = [&]() -> Process {
    seen.push_back(sim.now());
    co_await sim.delay(ns(5));
    seen.push_back(sim.now());
    co_await sim.delay(0);  // zero delay still yields
    seen.push_back(sim.now());
    co_await sim.delay_until(ns(12));
    seen.push_back(sim.now());
  };
  sim.spawn(body(), "p");
  EXPECT_EQ(sim.live_processes(), 1u);
  sim.run();
  EXPECT_EQ(seen, (std::vector<Time>{0, 5000, 5000, 12000}));
  EXPECT_EQ(sim.now(), 12000u);
  EXPECT_EQ(sim.events_processed(), 4u);  // start + three resumptions
  EXPECT_EQ(sim.live_processes(), 0u);
}

// Five processes all wake at t = 10 ns: order is priority (smaller first), then spawn order.
TEST(Simulator, SameTimeEventsRunByPriorityThenInsertion) {
  Simulator sim;
  Trace trace;
  sim.spawn(wait_and_log(sim, trace, "a", ns(10), 2));
  sim.spawn(wait_and_log(sim, trace, "b", ns(10), -1));
  sim.spawn(wait_and_log(sim, trace, "c", ns(10), 2));
  sim.spawn(wait_and_log(sim, trace, "d", ns(10), 0));
  sim.spawn(wait_and_log(sim, trace, "e", ns(9), 5));
  sim.run();
  const Trace expected = {{"e", 9000}, {"b", 10000}, {"d", 10000}, {"a", 10000}, {"c", 10000}};
  EXPECT_EQ(trace, expected);
}

TEST(Simulator, EventLogRecordsDispatchOrder) {
  Simulator sim;
  sim.enable_event_log();
  Trace trace;
  sim.spawn(wait_and_log(sim, trace, "x", ns(3), 1), "x");
  sim.spawn(wait_and_log(sim, trace, "y", ns(3), 0), "y");
  sim.run();
  const std::vector<EventRecord>& log = sim.event_log();
  ASSERT_EQ(log.size(), 4u);
  // Starts at t=0 in spawn order (sequence 0, 1), then y before x at 3 ns by priority.
  EXPECT_EQ(log[0].name, "x");
  EXPECT_EQ(log[0].sequence, 0u);
  EXPECT_EQ(log[1].name, "y");
  EXPECT_EQ(log[2].name, "y");
  EXPECT_EQ(log[2].time, 3000u);
  EXPECT_EQ(log[2].priority, 0);
  EXPECT_EQ(log[3].name, "x");
  EXPECT_EQ(log[3].priority, 1);
  EXPECT_EQ(log[3].process_id, 1u);
  EXPECT_EQ(log[3].kind, EventRecord::Kind::kResume);
}

// A model with random delays, a shared resource and a FIFO; run twice with the same seed the
// logs are identical, with another seed they differ.
std::vector<EventRecord> run_random_model(std::uint64_t seed) {
  Simulator sim;
  sim.enable_event_log();
  Resource unit(sim, 2, "unit");
  Fifo<int> queue(sim, 3, "queue");
  std::mt19937_64 random(seed);
  auto producer = [&](int id) -> Process {
    for (int i = 0; i < 20; ++i) {
      co_await sim.delay(random() % 1000 + 1);
      Lease lease = co_await unit.acquire();
      co_await sim.delay(random() % 500);
      co_await queue.put(id * 100 + i);
    }
  };
  auto consumer = [&]() -> Process {
    for (int i = 0; i < 80; ++i) {
      (void)co_await queue.get();
      co_await sim.delay(random() % 700);
    }
  };
  for (int id = 0; id < 4; ++id) sim.spawn(producer(id), "producer" + std::to_string(id));
  sim.spawn(consumer(), "consumer");
  sim.run();
  EXPECT_EQ(queue.gets(), 80u);
  return sim.event_log();
}

TEST(Simulator, TwoIdenticalRunsProduceIdenticalEventLogs) {
  const std::vector<EventRecord> first = run_random_model(7);
  const std::vector<EventRecord> second = run_random_model(7);
  const std::vector<EventRecord> other = run_random_model(8);
  ASSERT_GT(first.size(), 200u);
  EXPECT_EQ(first, second);
  EXPECT_NE(first, other);
}

// 300 processes with random delays (>= 1 ps, so every event at time t was queued before t) and
// random priorities: the dispatch order must be strictly increasing in (time, priority,
// sequence), and each process must end at the sum of its own delays. Large enough for the
// queue's timing wheel to be in use, with delays from ps to us so that it adapts.
TEST(Simulator, ManyProcessesDispatchInExactOrder) {
  Simulator sim;
  std::vector<EventRecord> log;
  sim.set_event_hook([&](const EventRecord& record) { log.push_back(record); });
  constexpr int kProcesses = 300;
  constexpr int kSteps = 200;
  std::vector<Time> expected_end(kProcesses, 0);
  std::vector<Time> actual_end(kProcesses, 0);
  const auto delay_of = [](std::mt19937_64& random) -> Time {
    switch (random() % 3) {
      case 0:
        return 1 + random() % 8;  // ps: many ties
      case 1:
        return ns(1 + random() % 1000);
      default:
        return us(1 + random() % 50);
    }
  };
  auto body = [&](int id) -> Process {
    std::mt19937_64 random(1000 + id);
    for (int step = 0; step < kSteps; ++step) {
      const Time delay = delay_of(random);
      co_await sim.delay(delay, static_cast<Priority>(random() % 7) - 3);
    }
    actual_end[id] = sim.now();
  };
  for (int id = 0; id < kProcesses; ++id) {
    std::mt19937_64 random(1000 + id);
    for (int step = 0; step < kSteps; ++step) {
      expected_end[id] += delay_of(random);
      random();  // the priority draw
    }
    sim.spawn(body(id), std::string("p").append(std::to_string(id)));
  }
  sim.run();
  EXPECT_EQ(actual_end, expected_end);
  ASSERT_EQ(log.size(), static_cast<std::size_t>(kProcesses) * (kSteps + 1));
  for (std::size_t i = 1; i < log.size(); ++i) {
    const auto previous =
        std::make_tuple(log[i - 1].time, log[i - 1].priority, log[i - 1].sequence);
    const auto current = std::make_tuple(log[i].time, log[i].priority, log[i].sequence);
    ASSERT_LT(previous, current) << "event " << i;
  }
}

TEST(Simulator, EventHookSeesEveryEvent) {
  Simulator sim;
  std::uint64_t calls = 0;
  Time last = 0;
  sim.set_event_hook([&](const EventRecord& record) {
    ++calls;
    EXPECT_GE(record.time, last);
    last = record.time;
  });
  Trace trace;
  for (int i = 0; i < 5; ++i) sim.spawn(wait_and_log(sim, trace, "p", ns(i), 0));
  sim.run();
  EXPECT_EQ(calls, sim.events_processed());
  EXPECT_TRUE(sim.event_log().empty());  // the log itself stays off
}

TEST(Simulator, JoinWaitsForChildren) {
  Simulator sim;
  Time joined_all = 0;
  Time joined_again = 0;
  auto child = [&](Time delay) -> Process { co_await sim.delay(delay); };
  auto parent = [&]() -> Process {
    ProcessHandle a = sim.spawn(child(ns(5)), "a");
    ProcessHandle b = sim.spawn(child(ns(15)), "b");
    ProcessHandle c = sim.spawn(child(ns(10)), "c");
    EXPECT_FALSE(a.done());
    co_await a;
    EXPECT_EQ(sim.now(), ns(5));
    co_await sim.join(b);
    co_await c;  // already finished at 10 ns: no wait
    joined_all = sim.now();
    EXPECT_TRUE(a.done() && b.done() && c.done());
    co_await a;  // joining a finished process again returns at once
    joined_again = sim.now();
  };
  sim.spawn(parent(), "parent");
  sim.run();
  EXPECT_EQ(joined_all, ns(15));
  EXPECT_EQ(joined_again, ns(15));
}

TEST(Simulator, SeveralJoinersAllResume) {
  Simulator sim;
  std::vector<Time> resumed;
  auto worker = [&]() -> Process { co_await sim.delay(ns(8)); };
  ProcessHandle handle = sim.spawn(worker(), "worker");
  auto waiter = [&]() -> Process {
    co_await handle;
    resumed.push_back(sim.now());
  };
  sim.spawn(waiter());
  sim.spawn(waiter());
  sim.run();
  EXPECT_EQ(resumed, (std::vector<Time>{ns(8), ns(8)}));
}

Task<int> add_after(Simulator& sim, int a, int b, Time delay) {
  co_await sim.delay(delay);
  co_return a + b;
}

Task<int> sum_twice(Simulator& sim) {
  const int first = co_await add_after(sim, 1, 2, ns(1));
  const int second = co_await add_after(sim, first, 10, ns(2));
  co_return second;
}

TEST(Simulator, AwaitedTasksRunAsSubroutines) {
  Simulator sim;
  int result = 0;
  auto top = [&]() -> Process { result = co_await sum_twice(sim); };
  sim.spawn(top());
  sim.run();
  EXPECT_EQ(result, 13);
  EXPECT_EQ(sim.now(), ns(3));
  EXPECT_EQ(sim.events_processed(), 3u);  // start + two delays; subroutine calls are free
}

Task<int> failing_task(Simulator& sim) {
  co_await sim.delay(ns(1));
  throw std::runtime_error("inner failure");
}

TEST(Simulator, ExceptionInAwaitedTaskReachesTheCaller) {
  Simulator sim;
  std::string caught;
  auto top = [&]() -> Process {
    try {
      (void)co_await failing_task(sim);
    } catch (const std::runtime_error& error) {
      caught = error.what();
    }
    co_await sim.delay(ns(1));
  };
  sim.spawn(top());
  EXPECT_NO_THROW(sim.run());
  EXPECT_EQ(caught, "inner failure");
  EXPECT_EQ(sim.now(), ns(2));
}

TEST(Simulator, ExceptionInProcessPropagatesOutOfRun) {
  Simulator sim;
  int survivor_steps = 0;
  auto failing = [&]() -> Process {
    co_await sim.delay(ns(7));
    throw std::runtime_error("boom");
  };
  auto survivor = [&]() -> Process {
    for (int i = 0; i < 3; ++i) {
      co_await sim.delay(ns(5));
      ++survivor_steps;
    }
  };
  sim.spawn(failing(), "failing");
  sim.spawn(survivor(), "survivor");
  try {
    sim.run();
    FAIL() << "run() swallowed the exception";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "boom");
  }
  EXPECT_EQ(sim.now(), ns(7));
  EXPECT_EQ(survivor_steps, 1);
  // The simulator stays usable: the survivor finishes.
  sim.run();
  EXPECT_EQ(survivor_steps, 3);
  EXPECT_EQ(sim.now(), ns(15));
}

TEST(Simulator, ExceptionPropagatesOutOfRunUntil) {
  Simulator sim;
  auto failing = [&]() -> Process {
    co_await sim.delay(ns(2));
    throw std::logic_error("bad state");
  };
  sim.spawn(failing());
  EXPECT_THROW(sim.run_until(ns(10)), std::logic_error);
  EXPECT_EQ(sim.now(), ns(2));
}

TEST(Simulator, RunUntilStopsAtTheLimitAndAdvancesTime) {
  Simulator sim;
  std::vector<Time> ticks;
  auto ticker = [&]() -> Process {
    for (;;) {
      co_await sim.delay(ns(4));
      ticks.push_back(sim.now());
    }
  };
  sim.spawn(ticker());
  sim.run_until(ns(10));
  EXPECT_EQ(ticks, (std::vector<Time>{ns(4), ns(8)}));
  EXPECT_EQ(sim.now(), ns(10));
  sim.run_until(ns(12));  // the event at exactly 12 ns is included
  EXPECT_EQ(ticks.back(), ns(12));
  EXPECT_THROW(sim.run_until(ns(11)), std::invalid_argument);
  EXPECT_EQ(sim.pending_events(), 1u);
}

TEST(Simulator, StopEndsRunAfterTheCurrentEvent) {
  Simulator sim;
  int steps = 0;
  auto worker = [&]() -> Process {
    for (int i = 0; i < 10; ++i) {
      co_await sim.delay(ns(1));
      if (++steps == 3) sim.stop();
    }
  };
  sim.spawn(worker());
  sim.run();
  EXPECT_EQ(steps, 3);
  EXPECT_EQ(sim.now(), ns(3));
  sim.run();
  EXPECT_EQ(steps, 10);
}

TEST(Simulator, CyclesWaitsForClockEdges) {
  Simulator sim;
  const ClockDomain clock("fpga", 150.0);  // edges at ceil(20000 n / 3) ps
  std::vector<Time> seen;
  auto body = [&]() -> Process {
    co_await sim.cycles(clock, 3);
    seen.push_back(sim.now());  // edge 3: 20000
    co_await sim.delay(1000);   // 21000, between edges 3 and 4
    co_await sim.cycles(clock, 1);
    seen.push_back(sim.now());  // edge 4: ceil(26666.67) = 26667
    co_await sim.cycles(clock, 0);
    seen.push_back(sim.now());  // already on an edge: stays
    co_await sim.delay(1);
    co_await sim.cycles(clock, 0);
    seen.push_back(sim.now());  // next edge 5: ceil(33333.33) = 33334
  };
  sim.spawn(body());
  sim.run();
  EXPECT_EQ(seen, (std::vector<Time>{20000, 26667, 26667, 33334}));
}

// advance(): alone in the queue, the process goes on in place (no event); the times are
// delay()'s and cycles()'s.
TEST(Simulator, AdvanceAloneMovesTheClockWithoutAnEvent) {
  Simulator sim;
  const ClockDomain clock("fpga", 150.0);  // edges at ceil(20000 n / 3) ps
  std::vector<Time> seen;
  auto body = [&]() -> Process {
    co_await sim.advance(ns(5));
    seen.push_back(sim.now());
    co_await sim.advance_cycles(clock, 1);
    seen.push_back(sim.now());  // edge 1 after 5000: edge 1 = 6667
    co_await sim.advance(1);
    co_await sim.advance_cycles(clock, 0);
    seen.push_back(sim.now());  // next edge 2: ceil(13333.33) = 13334
  };
  sim.spawn(body(), "p");
  sim.run();
  EXPECT_EQ(seen, (std::vector<Time>{5000, 6667, 13334}));
  EXPECT_EQ(sim.now(), 13334u);
  EXPECT_EQ(sim.events_processed(), 1u);  // the start only
}

// With another event queued before or at its time, advance() waits as delay() does: the
// same order of work as delay() gives (an event at the same time that was queued first runs
// first), and the resumption is an event.
TEST(Simulator, AdvanceWaitsWhenAnotherEventComesFirst) {
  for (const bool in_place : {false, true}) {
    SCOPED_TRACE(in_place);
    Simulator sim;
    Trace trace;
    const auto step = [&](std::string name, Time d) -> Process {
      co_await (in_place ? sim.advance(d) : sim.delay(d));
      trace.emplace_back(name + "1", sim.now());
      co_await (in_place ? sim.advance(d) : sim.delay(d));
      trace.emplace_back(name + "2", sim.now());
    };
    sim.spawn(step("b", ns(10)));  // b at 10 and 20
    sim.spawn(step("a", ns(10)));  // a at 10 (after b: queued later) and 20
    sim.spawn(wait_and_log(sim, trace, "c", ns(15), 0));
    sim.run();
    const Trace expected = {
        {"b1", 10000}, {"a1", 10000}, {"c", 15000}, {"b2", 20000}, {"a2", 20000}};
    EXPECT_EQ(trace, expected);
    EXPECT_EQ(sim.events_processed(), 8u);  // 3 starts, a and b each twice, c once
  }
}

// With an event log on, advance() is delay(): every resumption is an event and is logged.
TEST(Simulator, AdvanceIsAnEventWhileLogging) {
  Simulator sim;
  sim.enable_event_log();
  auto body = [&]() -> Process { co_await sim.advance(ns(5)); };
  sim.spawn(body(), "p");
  sim.run();
  EXPECT_EQ(sim.now(), 5000u);
  EXPECT_EQ(sim.events_processed(), 2u);
  ASSERT_EQ(sim.event_log().size(), 2u);
  EXPECT_EQ(sim.event_log()[1].time, 5000u);
}

TEST(Simulator, RejectsBadArguments) {
  Simulator sim;
  EXPECT_THROW(sim.spawn(Process{}), std::invalid_argument);
  auto body = [&]() -> Process {
    co_await sim.delay(ns(5));
    EXPECT_THROW(sim.delay_until(ns(1)), std::invalid_argument);
    EXPECT_THROW(sim.delay(kTimeMax), std::overflow_error);
    EXPECT_THROW(sim.run(), std::logic_error);  // no nested runs
  };
  sim.spawn(body());
  sim.run();
  EXPECT_EQ(sim.now(), ns(5));
}

// Counts live instances; lives in coroutine frames to observe their destruction.
struct FrameProbe {
  explicit FrameProbe(int& live) : live_(&live) { ++*live_; }
  FrameProbe(const FrameProbe&) = delete;
  ~FrameProbe() { --*live_; }
  int* live_;
};

TEST(Simulator, DestroyingWithSuspendedProcessesFreesEverything) {
  int live = 0;
  {
    Simulator sim;
    Resource unit(sim, 1, "unit");
    Fifo<std::string> fifo(sim, 1, "fifo");
    Event never(sim, "never");
    auto sleeper = [&]() -> Process {
      FrameProbe probe(live);
      co_await sim.delay(ms(1));
    };
    auto holder = [&]() -> Process {
      FrameProbe probe(live);
      Lease lease = co_await unit.acquire();
      co_await never;
    };
    auto queued = [&]() -> Process {
      FrameProbe probe(live);
      Lease lease = co_await unit.acquire();  // waits behind holder forever
    };
    auto blocked_putter = [&]() -> Process {
      FrameProbe probe(live);
      co_await fifo.put("first");
      co_await fifo.put("second");  // blocks: capacity 1
    };
    auto nested = [&]() -> Process {
      FrameProbe probe(live);
      co_await [&]() -> Task<int> {
        FrameProbe inner(live);
        co_await sim.all_of({never});
        co_return 1;
      }();
    };
    auto never_started = [&]() -> Process {
      FrameProbe probe(live);
      co_return;
    };
    sim.spawn(sleeper());
    sim.spawn(holder());
    sim.spawn(queued());
    sim.spawn(blocked_putter());
    sim.spawn(nested());
    sim.run_until(ns(1));
    sim.spawn(never_started());  // spawned but never run
    EXPECT_EQ(live, 6);
    EXPECT_EQ(sim.live_processes(), 6u);
    EXPECT_EQ(unit.queue_length(), 1u);
  }
  EXPECT_EQ(live, 0);
}

TEST(Simulator, ManyShortProcessesRecycleTheirRecords) {
  Simulator sim;
  std::uint64_t finished = 0;
  // Coroutine lambdas reach their captures through the closure object, so the closure must
  // outlive the coroutine: keep it named, never spawn a temporary lambda's coroutine.
  auto child_body = [&]() -> Process {
    co_await sim.delay(ns(1));
    ++finished;
  };
  auto spawner = [&]() -> Process {
    for (int i = 0; i < 1000; ++i) {
      ProcessHandle child = sim.spawn(child_body());
      co_await child;
    }
  };
  sim.spawn(spawner());
  sim.run();
  EXPECT_EQ(finished, 1000u);
  EXPECT_EQ(sim.now(), ns(1000));
  EXPECT_EQ(sim.live_processes(), 0u);
}

}  // namespace
}  // namespace edx::sim
