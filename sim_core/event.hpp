#pragma once
// Events: named notification points processes can wait on.
//
// Semantics (documented in docs/SIM_CORE.md): an Event carries no state; a notification wakes
// the coroutines waiting at that moment and is lost if nobody waits. Woken coroutines are
// scheduled at the notification time with the notification's priority, behind the events already
// queued for that (time, priority), in the order they started waiting.
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim_core/simulator.hpp"
#include "sim_core/wait_list.hpp"

namespace edx::sim {

/// Awaiter of `co_await event`: resumes at the event's next notification.
class EventAwaiter {
 public:
  explicit EventAwaiter(Event& event) noexcept : event_(&event) {}
  bool await_ready() const noexcept { return false; }
  template <class Promise>
  void await_suspend(std::coroutine_handle<Promise> handle) noexcept {
    node_.handle = handle;
    node_.process = detail::process_of(handle);
    enqueue();
  }
  void await_resume() const noexcept {}

 private:
  void enqueue() noexcept;

  Event* event_;
  detail::WaiterNode node_;
};

/// A notification point. `co_await event` waits for the next notification; notify() wakes the
/// current waiters now, notify_at()/notify_after() at a later time (several timed notifications
/// may be pending; each one fires). Must be destroyed before its Simulator.
class alignas(8) Event {
 public:
  /// An event of `sim`; `name` labels its timed notifications in the event log.
  explicit Event(Simulator& sim, std::string name = {});
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;
  /// Cancels pending timed notifications; coroutines still waiting stay suspended.
  ~Event();

  /// Wakes every coroutine waiting now; they resume at now() with `priority`.
  void notify(Priority priority = 0);
  /// Fires the event at absolute time `when` (>= now()).
  void notify_at(Time when, Priority priority = 0);
  /// Fires the event `delay` ps from now.
  void notify_after(Time delay, Priority priority = 0);

  /// Waits for the next notification.
  EventAwaiter operator co_await() noexcept { return EventAwaiter(*this); }

  /// Number of coroutines waiting (including members of all_of / any_of waits).
  std::size_t waiting() const noexcept { return waiters_.size(); }
  /// Number of times the event has fired (immediate and timed notifications).
  std::uint64_t notifications() const noexcept { return notifications_; }
  /// Timed notifications not yet fired.
  std::size_t pending_notifications() const noexcept { return pending_timed_; }
  /// The name given at construction.
  const std::string& name() const noexcept { return name_; }

 private:
  friend class Simulator;
  friend class EventAwaiter;
  friend class detail::CompositeWait;

  void fire(Priority priority);
  void fire_scheduled(Priority priority);

  Simulator* sim_;
  std::string name_;
  detail::WaitList waiters_;
  std::size_t pending_timed_ = 0;
  std::uint64_t notifications_ = 0;
};

}  // namespace edx::sim
