#pragma once
// Bounded FIFO stores with back-pressure.
//
//   Fifo<Packet> link(sim, 4, "fd_to_fc");
//   co_await link.put(packet);        // suspends while the FIFO holds 4 items
//   Packet p = co_await link.get();   // suspends while it is empty
//
// Blocked putters and getters are served in arrival order. A put meeting a waiting getter hands
// the item over directly; a get from a full FIFO with waiting putters admits the oldest putter's
// item in the same instant, and that putter resumes at that time.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim_core/simulator.hpp"
#include "sim_core/stats.hpp"
#include "sim_core/wait_list.hpp"

namespace edx::sim {

/// A bounded FIFO of T with blocking put/get and occupancy statistics. Must be destroyed before
/// its Simulator.
template <class T>
class Fifo {
 public:
  /// Awaiter of `co_await fifo.put(item)`.
  class PutAwaiter : private detail::WaiterNode {
   public:
    PutAwaiter(Fifo& fifo, T item) : fifo_(&fifo), item_(std::move(item)) {}
    bool await_ready() { return fifo_->offer(item_); }
    template <class Promise>
    void await_suspend(std::coroutine_handle<Promise> coroutine) noexcept {
      this->handle = coroutine;
      this->process = detail::process_of(coroutine);
      fifo_->putters_.push_back(this);
    }
    void await_resume() const noexcept {}

   private:
    friend class Fifo;
    Fifo* fifo_;
    T item_;
  };

  /// Awaiter of `co_await fifo.get()`; yields the item.
  class GetAwaiter : private detail::WaiterNode {
   public:
    explicit GetAwaiter(Fifo& fifo) : fifo_(&fifo) {}
    bool await_ready() { return fifo_->take(slot_); }
    template <class Promise>
    void await_suspend(std::coroutine_handle<Promise> coroutine) noexcept {
      this->handle = coroutine;
      this->process = detail::process_of(coroutine);
      fifo_->getters_.push_back(this);
    }
    T await_resume() { return std::move(*slot_); }

   private:
    friend class Fifo;
    Fifo* fifo_;
    std::optional<T> slot_;
  };

  /// A FIFO holding at most `capacity` >= 1 items; throws std::invalid_argument otherwise.
  Fifo(Simulator& sim, std::size_t capacity, std::string name = {})
      : sim_(&sim), name_(std::move(name)), capacity_(capacity), occupancy_(sim) {
    if (capacity == 0) {
      throw std::invalid_argument("edx::sim::Fifo '" + name_ + "': capacity must be >= 1");
    }
  }
  Fifo(const Fifo&) = delete;
  Fifo& operator=(const Fifo&) = delete;

  /// `co_await fifo.put(item)`: appends `item`, waiting while the FIFO is full.
  PutAwaiter put(T item) { return PutAwaiter(*this, std::move(item)); }
  /// `T item = co_await fifo.get()`: removes the oldest item, waiting while the FIFO is empty.
  GetAwaiter get() { return GetAwaiter(*this); }
  /// Appends `item` if that needs no wait; returns false (item untouched) otherwise.
  bool try_put(T& item) { return offer(item); }
  /// Removes the oldest item if there is one, without waiting.
  std::optional<T> try_get() {
    std::optional<T> slot;
    take(slot);
    return slot;
  }

  /// The name given at construction.
  const std::string& name() const noexcept { return name_; }
  /// Maximum number of items held.
  std::size_t capacity() const noexcept { return capacity_; }
  /// Items held now.
  std::size_t size() const noexcept { return items_.size(); }
  /// True when no item is held.
  bool empty() const noexcept { return items_.empty(); }
  /// True when size() == capacity().
  bool full() const noexcept { return items_.size() == capacity_; }
  /// Processes blocked in put().
  std::size_t waiting_putters() const noexcept { return putters_.size(); }
  /// Processes blocked in get().
  std::size_t waiting_getters() const noexcept { return getters_.size(); }
  /// Items accepted so far.
  std::uint64_t puts() const noexcept { return puts_; }
  /// Items delivered so far.
  std::uint64_t gets() const noexcept { return gets_; }
  /// Items held over time (time-weighted mean occupancy, max occupancy).
  const TimeWeighted& occupancy() const noexcept { return occupancy_; }

 private:
  /// Accepts `item` now if possible (moving from it); false if the caller must wait.
  bool offer(T& item) {
    if (!getters_.empty()) {
      // Empty FIFO with a waiting getter: hand over directly.
      auto* getter = static_cast<GetAwaiter*>(getters_.pop_front());
      getter->slot_.emplace(std::move(item));
      ++puts_;
      ++gets_;
      sim_->wake(*getter);
      return true;
    }
    if (items_.size() < capacity_ && putters_.empty()) {
      items_.push_back(std::move(item));
      ++puts_;
      occupancy_.set(static_cast<double>(items_.size()));
      return true;
    }
    return false;
  }

  /// Delivers the oldest item into `slot` if there is one; false if the caller must wait.
  bool take(std::optional<T>& slot) {
    if (items_.empty()) return false;
    slot.emplace(std::move(items_.front()));
    items_.pop_front();
    ++gets_;
    if (!putters_.empty()) {
      // A slot just freed: admit the oldest blocked putter's item and wake it.
      auto* putter = static_cast<PutAwaiter*>(putters_.pop_front());
      items_.push_back(std::move(putter->item_));
      ++puts_;
      sim_->wake(*putter);
    }
    occupancy_.set(static_cast<double>(items_.size()));
    return true;
  }

  Simulator* sim_;
  std::string name_;
  std::size_t capacity_;
  std::deque<T> items_;
  detail::WaitList putters_;
  detail::WaitList getters_;
  std::uint64_t puts_ = 0;
  std::uint64_t gets_ = 0;
  TimeWeighted occupancy_;
};

}  // namespace edx::sim
