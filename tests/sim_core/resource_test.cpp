// Resources: FIFO service under contention with exact start/finish times, RAII and explicit
// release, utilization.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sim_core/engine.hpp"

namespace edx::sim {
namespace {

struct Service {
  std::string name;
  Time start;
  Time finish;
  bool operator==(const Service&) const = default;
};

// Capacity 2; customers (arrival, service) in ns: c0 (0, 10), c1 (1, 3), c2 (2, 4), c3 (3, 1),
// c4 (3, 2) -- c4 is spawned after c3 so it queues behind it at the same instant.
//   t=0  c0 takes unit A (until 10)        t=1  c1 takes unit B (until 4)
//   t=2  c2 queues [c2]                    t=3  c3, c4 queue [c2 c3 c4]
//   t=4  c1 leaves, c2 gets B (until 8)    t=8  c2 leaves, c3 gets B (until 9)
//   t=9  c3 leaves, c4 gets B (until 11)   t=10 c0 leaves, nobody waits; t=11 c4 leaves.
// Busy units: [0,1) 1, [1,10) 2, [10,11) 1 -> integral 20 unit*ns over 11 ns,
// utilization 20 / (2 * 11) = 10/11. Queue length: [2,3) 1, [3,4) 3, [4,8) 2, [8,9) 1, else 0
// -> integral 1 + 3 + 8 + 1 = 13 ns, mean 13/11.
TEST(Resource, ContendedUnitsServeWaitersInArrivalOrder) {
  Simulator sim;
  Resource unit(sim, 2, "dsp");
  std::vector<Service> served;
  auto customer = [&](std::string name, Time arrival, Time service) -> Process {
    co_await sim.delay(arrival);
    Lease lease = co_await unit.acquire();
    const Time start = sim.now();
    co_await sim.delay(service);
    served.push_back({name, start, sim.now()});
  };
  sim.spawn(customer("c0", ns(0), ns(10)));
  sim.spawn(customer("c1", ns(1), ns(3)));
  sim.spawn(customer("c2", ns(2), ns(4)));
  sim.spawn(customer("c3", ns(3), ns(1)));
  sim.spawn(customer("c4", ns(3), ns(2)));
  sim.run();
  const std::vector<Service> expected = {{"c1", ns(1), ns(4)},
                                         {"c2", ns(4), ns(8)},
                                         {"c3", ns(8), ns(9)},
                                         {"c0", ns(0), ns(10)},
                                         {"c4", ns(9), ns(11)}};
  EXPECT_EQ(served, expected);
  EXPECT_EQ(sim.now(), ns(11));
  EXPECT_EQ(unit.in_use(), 0u);
  EXPECT_EQ(unit.acquisitions(), 5u);
  EXPECT_DOUBLE_EQ(unit.busy().integral(), 20.0 * 1000);  // unit * ps
  EXPECT_DOUBLE_EQ(unit.utilization(), 10.0 / 11.0);
  EXPECT_DOUBLE_EQ(unit.busy().max(), 2.0);
  EXPECT_DOUBLE_EQ(unit.queue().mean(), 13.0 / 11.0);
  EXPECT_DOUBLE_EQ(unit.queue().max(), 3.0);
}

// A unit released while others wait goes to the oldest waiter even if a newcomer asks in the
// same instant: no barging.
/// Two uses of a one-unit resource, [request, release) in ns, lived through by processes that
/// acquire at the request and hold the unit until the release (the second one waits when it asks
/// before the first's release), or booked afterwards with book_idle: the same statistics.
struct TwoUses {
  double busy_integral, busy_max, queue_integral, queue_max;
  std::uint64_t acquisitions;
};
TwoUses two_uses(Resource::Use a, Resource::Use b, bool book) {
  Simulator sim;
  Resource unit(sim, 1, "unit");
  auto hold = [&](Resource::Use u) -> Process {
    co_await sim.delay_until(u.request);
    Lease lease = co_await unit.acquire();
    co_await sim.delay_until(u.release);
  };
  auto booker = [&]() -> Process {
    co_await sim.delay_until(b.release);
    const Resource::Use uses[] = {a, b};
    unit.book_idle(uses, 2);
  };
  if (book) {
    sim.spawn(booker());
  } else {
    sim.spawn(hold(a));
    sim.spawn(hold(b));
  }
  sim.run_until(b.release + ns(10));
  EXPECT_EQ(unit.in_use(), 0u);
  return {unit.busy().integral(), unit.busy().max(), unit.queue().integral(), unit.queue().max(),
          unit.acquisitions()};
}

TEST(Resource, BookIdleLeavesTheStatisticsOfAcquireAndRelease) {
  // Handed over: a [0, 10), b asks at 4 and gets the unit at 10, releases at 15. Busy 15 ns
  // without a break, queue length 1 over [4, 10).
  const Resource::Use a{ns(0), ns(10)}, b{ns(4), ns(15)};
  for (bool book : {false, true}) {
    const TwoUses u = two_uses(a, b, book);
    EXPECT_EQ(u.busy_integral, 15.0 * 1000) << book;
    EXPECT_EQ(u.busy_max, 1.0);
    EXPECT_EQ(u.queue_integral, 6.0 * 1000) << book;
    EXPECT_EQ(u.queue_max, 1.0);
    EXPECT_EQ(u.acquisitions, 2u);
  }
  // Apart: b asks at 12 (the unit free since 10) and holds it until 20: busy 18 ns, no queue.
  for (bool book : {false, true}) {
    const TwoUses u = two_uses(a, {ns(12), ns(20)}, book);
    EXPECT_EQ(u.busy_integral, 18.0 * 1000) << book;
    EXPECT_EQ(u.queue_integral, 0.0) << book;
    EXPECT_EQ(u.queue_max, 0.0);
    EXPECT_EQ(u.acquisitions, 2u);
  }
}

TEST(Resource, BookIdleRefusesABusyUnitAndUnorderedUses) {
  Simulator sim;
  Resource unit(sim, 1, "unit"), pair(sim, 2, "pair");
  const Resource::Use first{ns(0), ns(10)}, early{ns(0), ns(5)};
  auto run = [&]() -> Process {
    co_await sim.delay(ns(20));
    const Resource::Use backwards[] = {first, early};  // released before the previous one
    EXPECT_THROW(unit.book_idle(backwards, 2), std::logic_error);
    // Two waiting at once (c asks before b, which waits for a, has the unit).
    const Resource::Use two_waiting[] = {first, {ns(2), ns(12)}, {ns(3), ns(14)}};
    EXPECT_THROW(unit.book_idle(two_waiting, 3), std::logic_error);
    const Resource::Use future[] = {{ns(0), ns(30)}};  // released after now
    EXPECT_THROW(unit.book_idle(future, 1), std::logic_error);
    EXPECT_THROW(pair.book_idle(&first, 1), std::logic_error);  // two units
    Lease lease = co_await unit.acquire();
    EXPECT_THROW(unit.book_idle(&first, 1), std::logic_error);  // held
  };
  sim.spawn(run());
  sim.run();
  EXPECT_EQ(unit.acquisitions(), 1u);  // only the lease: nothing booked
  EXPECT_EQ(unit.busy().integral(), 0.0);
  EXPECT_EQ(unit.queue().integral(), 0.0);
}

TEST(Resource, NewcomerCannotOvertakeAWaiter) {
  Simulator sim;
  Resource unit(sim, 1, "port");
  std::vector<std::string> order;
  auto user = [&](std::string name, Time arrival) -> Process {
    co_await sim.delay(arrival);
    Lease lease = co_await unit.acquire();
    order.push_back(name);
    co_await sim.delay(ns(5));
  };
  auto barger = [&]() -> Process {
    // At t=5 this runs before "first" resumes and releases (priority -1 < 0): the unit is
    // still held and "second" already waits, so it must queue behind "second".
    co_await sim.delay(ns(5), -1);
    EXPECT_FALSE(unit.try_acquire());
    Lease lease = co_await unit.acquire();
    order.push_back("barger");
  };
  sim.spawn(user("first", 0));
  sim.spawn(user("second", ns(1)));
  sim.spawn(barger());
  sim.run();
  EXPECT_EQ(order, (std::vector<std::string>{"first", "second", "barger"}));
}

TEST(Resource, HandedOverUnitIsNotAvailableToTryAcquire) {
  Simulator sim;
  Resource unit(sim, 1, "port");
  bool newcomer_got_unit = true;
  auto holder = [&]() -> Process {
    Lease lease = co_await unit.acquire();
    co_await sim.delay(ns(2));
    lease.release();  // explicit release hands the unit to the waiter at once
    EXPECT_FALSE(lease.held());
    newcomer_got_unit = static_cast<bool>(unit.try_acquire());
    co_await sim.delay(ns(1));
  };
  Time waiter_start = 0;
  auto waiter = [&]() -> Process {
    co_await sim.delay(ns(1));
    Lease lease = co_await unit.acquire();
    waiter_start = sim.now();
  };
  sim.spawn(holder());
  sim.spawn(waiter());
  sim.run();
  EXPECT_FALSE(newcomer_got_unit);
  EXPECT_EQ(waiter_start, ns(2));
}

TEST(Resource, LeasesMoveAndReleaseOnce) {
  Simulator sim;
  Resource unit(sim, 3, "pool");
  Lease a = unit.try_acquire();
  Lease b = unit.try_acquire();
  EXPECT_TRUE(a.held());
  EXPECT_EQ(unit.in_use(), 2u);
  Lease moved = std::move(a);
  EXPECT_FALSE(a.held());  // NOLINT(bugprone-use-after-move): checking the moved-from state
  EXPECT_EQ(moved.resource(), &unit);
  EXPECT_EQ(unit.in_use(), 2u);
  moved.release();
  moved.release();  // second release is a no-op
  EXPECT_EQ(unit.in_use(), 1u);
  b = unit.try_acquire();  // assignment releases the old unit first
  EXPECT_EQ(unit.in_use(), 1u);
  {
    Lease scoped = unit.try_acquire();
    EXPECT_EQ(unit.in_use(), 2u);
  }
  EXPECT_EQ(unit.in_use(), 1u);
  EXPECT_EQ(unit.available(), 2u);
  EXPECT_THROW(Resource(sim, 0, "empty"), std::invalid_argument);
}

}  // namespace
}  // namespace edx::sim
