#pragma once
// Resources: a pool of identical units (a matrix unit, a DMA engine, a memory port) that
// processes hold for a while. Waiters are served strictly in arrival order (FIFO): a unit freed
// while others wait is handed directly to the oldest waiter, and a newcomer never overtakes a
// waiter even if it arrives at the same instant.
//
//   Resource unit(sim, 2, "dsp");
//   {
//     Lease lease = co_await unit.acquire();  // waits while both units are busy
//     co_await sim.delay(ns(40));
//   }                                         // lease destroyed: unit released
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim_core/simulator.hpp"
#include "sim_core/stats.hpp"
#include "sim_core/wait_list.hpp"

namespace edx::sim {

class Resource;

/// Ownership of one unit of a Resource. Move-only; releases the unit when destroyed (RAII) or on
/// release(). An empty Lease holds nothing.
class Lease {
 public:
  Lease() noexcept = default;
  Lease(Lease&& other) noexcept;
  Lease& operator=(Lease&& other) noexcept;
  Lease(const Lease&) = delete;
  Lease& operator=(const Lease&) = delete;
  ~Lease() { release(); }

  /// Gives the unit back now (no-op for an empty lease). During simulator teardown it only
  /// forgets the unit.
  void release() noexcept;
  /// True while a unit is held.
  bool held() const noexcept { return resource_ != nullptr; }
  explicit operator bool() const noexcept { return held(); }
  /// The resource the unit belongs to (nullptr when empty).
  Resource* resource() const noexcept { return resource_; }

 private:
  friend class Resource;
  friend class AcquireAwaiter;
  explicit Lease(Resource* resource) noexcept;

  Resource* resource_ = nullptr;
  Simulator* sim_ = nullptr;
};

/// Awaiter of `co_await resource.acquire()`; yields a Lease.
class AcquireAwaiter {
 public:
  explicit AcquireAwaiter(Resource& resource) noexcept : resource_(&resource) {}
  bool await_ready() noexcept;
  template <class Promise>
  void await_suspend(std::coroutine_handle<Promise> handle) noexcept {
    node_.handle = handle;
    node_.process = detail::process_of(handle);
    enqueue();
  }
  Lease await_resume() noexcept;

 private:
  void enqueue() noexcept;

  Resource* resource_;
  detail::WaiterNode node_;
};

/// A pool of `capacity` identical units with a FIFO queue of waiting processes, plus its
/// statistics (units busy and queue length over time). Must be destroyed before its Simulator.
class Resource {
 public:
  /// A resource of `capacity` >= 1 units; throws std::invalid_argument otherwise.
  Resource(Simulator& sim, std::size_t capacity, std::string name = {});
  Resource(const Resource&) = delete;
  Resource& operator=(const Resource&) = delete;

  /// `Lease lease = co_await resource.acquire();` -- waits (FIFO) for a free unit.
  AcquireAwaiter acquire() noexcept { return AcquireAwaiter(*this); }
  /// A lease if a unit is free and nobody waits, else an empty lease; never suspends.
  Lease try_acquire() noexcept;

  /// One use of a unit computed by its model instead of simulated (book_idle).
  struct Use {
    Time request = 0;  ///< asked for the unit
    Time release = 0;  ///< gave it back
  };
  /// Records uses that a model computed for this resource while it could run alone (no other
  /// process between now and the last release: Simulator::try_advance_in_place), with the
  /// statistics and counters that acquire() at each request and release at each release would
  /// have left: a use asked for before the previous one's release waited (queue length 1) and got
  /// the unit at that release, handed over (busy stays 1); else it took the free unit at its
  /// request. Its grant is then max(request, previous release). Requires one unit, idle with no
  /// waiter, uses in order with request <= release, each asked for no earlier than the previous
  /// one's grant (at most one waiter) and released no earlier than the previous one, every time
  /// between the statistics' last change and now(); std::logic_error otherwise (nothing
  /// recorded).
  void book_idle(const Use* uses, std::size_t count);

  /// The name given at construction.
  const std::string& name() const noexcept { return name_; }
  /// Number of units.
  std::size_t capacity() const noexcept { return capacity_; }
  /// Units currently held.
  std::size_t in_use() const noexcept { return in_use_; }
  /// Units currently free.
  std::size_t available() const noexcept { return capacity_ - in_use_; }
  /// Processes waiting for a unit.
  std::size_t queue_length() const noexcept { return waiters_.size(); }
  /// Leases granted so far.
  std::uint64_t acquisitions() const noexcept { return acquisitions_; }
  /// Units busy over time (its mean is the average number of busy units).
  const TimeWeighted& busy() const noexcept { return busy_; }
  /// Queue length over time.
  const TimeWeighted& queue() const noexcept { return queue_; }
  /// Mean fraction of the capacity busy since construction: busy().mean() / capacity().
  double utilization() const { return busy_.mean() / static_cast<double>(capacity_); }

 private:
  friend class Lease;
  friend class AcquireAwaiter;

  bool try_take() noexcept;
  void enqueue(detail::WaiterNode* node) noexcept;
  void release_unit() noexcept;

  Simulator* sim_;
  std::string name_;
  std::size_t capacity_;
  std::size_t in_use_ = 0;
  std::uint64_t acquisitions_ = 0;
  detail::WaitList waiters_;
  TimeWeighted busy_;
  TimeWeighted queue_;
};

}  // namespace edx::sim
