#pragma once
// The discrete-event simulator: simulated clock, pending-event queue, process scheduling.
//
// Determinism: pending events are ordered by (time, priority, insertion sequence) and nothing
// else (no addresses, no hashing), so the same model run twice processes the same events in the
// same order; enable_event_log() records that order for comparison.
#include <algorithm>
#include <concepts>
#include <coroutine>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "sim_core/clock.hpp"
#include "sim_core/event_queue.hpp"
#include "sim_core/process.hpp"
#include "sim_core/time.hpp"
#include "sim_core/wait_list.hpp"

namespace edx::sim {

class Event;
class Simulator;

/// One processed event, as recorded by the event log / passed to the event hook.
struct EventRecord {
  /// What the event did.
  enum class Kind : std::uint8_t {
    kResume,  ///< resumed (or started) a process
    kNotify,  ///< fired a timed Event notification
  };
  Time time = 0;
  Priority priority = 0;
  std::uint64_t sequence = 0;  ///< insertion number (unique per simulator)
  Kind kind = Kind::kResume;
  std::uint64_t process_id = 0;  ///< resumed process (spawn number), 0 if unknown / kNotify
  std::string name;              ///< process name, or the event name for kNotify

  bool operator==(const EventRecord&) const = default;
};

/// Awaiter of sim.delay(), sim.delay_until() and sim.cycles(): suspends until an absolute time.
/// Always suspends (a zero delay yields to the events already queued for the current time).
/// sim.advance() and sim.advance_cycles(): the same, except that when nothing else can happen
/// until that time it moves the clock there in place (Simulator::advance).
class TimerAwaiter {
 public:
  TimerAwaiter(Simulator& sim, Time when, Priority priority, bool in_place = false) noexcept
      : sim_(&sim), when_(when), priority_(priority), in_place_(in_place) {}
  bool await_ready() const;  ///< not noexcept: advance's test may grow the queue's near heap
  template <class Promise>
  void await_suspend(std::coroutine_handle<Promise> handle) const;
  void await_resume() const noexcept {}

 private:
  Simulator* sim_;
  Time when_;
  Priority priority_;
  bool in_place_;
};

/// The events of an all_of / any_of wait, written `{e1, e2, ...}` (Event lvalues) or given as a
/// vector of pointers. (Not a std::initializer_list: GCC 12 cannot keep an initializer_list's
/// backing array alive across a co_await -- "array used as initializer".)
class EventList {
 public:
  /// No events.
  EventList() = default;
  /// `{e1, e2, ...}`.
  template <std::same_as<Event>... Events>
  EventList(Events&... events) : events_{&events...} {}  // NOLINT(google-explicit-constructor)
  /// A list built elsewhere (must not contain nullptr).
  EventList(std::vector<Event*> events)  // NOLINT(google-explicit-constructor)
      : events_(std::move(events)) {}

  /// The events, in order.
  std::vector<Event*>& events() noexcept { return events_; }

 private:
  std::vector<Event*> events_;
};

namespace detail {

/// Common part of all_of / any_of: one WaiterNode per event, linked into each event's list.
class CompositeWait {
 public:
  CompositeWait(Simulator& sim, std::vector<Event*> events, bool wait_for_any);
  CompositeWait(CompositeWait&&) = default;
  CompositeWait(const CompositeWait&) = delete;
  CompositeWait& operator=(const CompositeWait&) = delete;

  bool await_ready() const noexcept { return events_.empty(); }
  template <class Promise>
  void await_suspend(std::coroutine_handle<Promise> handle) {
    suspend(handle, process_of(handle));
  }

  /// Called by Event when `node` (one of ours) is notified.
  void member_fired(WaiterNode& node, Priority priority);

 protected:
  void suspend(std::coroutine_handle<> handle, ProcessRecord* process);

  Simulator* sim_;
  std::vector<Event*> events_;
  std::vector<WaiterNode> nodes_;
  bool wait_for_any_;
  bool finished_ = false;
  std::size_t remaining_ = 0;    ///< all_of: events not yet notified
  std::size_t fired_index_ = 0;  ///< any_of: which event fired first
  std::coroutine_handle<> handle_;
  ProcessRecord* process_ = nullptr;
};

}  // namespace detail

/// Awaiter of sim.all_of(...): resumes once every listed event has been notified at least once
/// since the wait began (immediately for an empty list).
class AllOfAwaiter : public detail::CompositeWait {
 public:
  using CompositeWait::CompositeWait;
  void await_resume() const noexcept {}
};

/// Awaiter of sim.any_of(...): resumes at the first notification of any listed event and yields
/// that event's index in the list.
class AnyOfAwaiter : public detail::CompositeWait {
 public:
  using CompositeWait::CompositeWait;
  std::size_t await_resume() const noexcept { return fired_index_; }
};

/// The discrete-event simulator. Owns its spawned processes; Events, Resources, Fifos and stats
/// bound to it must be destroyed before it (declare the Simulator first). Destroying a simulator
/// with suspended processes destroys their coroutine frames (no leak; Leases held by them are
/// dropped without waking anyone). Not thread-safe; one simulator per thread.
class Simulator {
 public:
  Simulator() = default;
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;
  ~Simulator();

  /// Current simulated time.
  Time now() const noexcept { return now_; }
  /// Number of events dispatched so far (process starts/resumptions and timed notifications).
  std::uint64_t events_processed() const noexcept { return events_processed_; }
  /// Number of pending events.
  std::size_t pending_events() const noexcept { return queue_.size(); }
  /// Number of spawned processes that have not finished.
  std::size_t live_processes() const noexcept { return live_processes_; }

  /// Starts `process` as an independent process named `name` (default "process#<id>"): its
  /// first step is scheduled at now() with priority 0, i.e. after the events already queued for
  /// now() with priority <= 0. Returns a handle that can be awaited (join). Throws
  /// std::invalid_argument for an empty or already started Process.
  ProcessHandle spawn(Process process, std::string name = {});

  /// `co_await sim.delay(d)`: resume `duration` ps from now. Throws TimeRangeError when
  /// now() + duration reaches kTimeMax (reserved; no event can be scheduled there).
  TimerAwaiter delay(Time duration, Priority priority = 0) {
    return TimerAwaiter(*this, delay_end(duration), priority);
  }
  /// `co_await sim.delay_until(t)`: resume at absolute time t (>= now()).
  TimerAwaiter delay_until(Time when, Priority priority = 0);
  /// `co_await sim.cycles(clock, n)`: resume at the n-th rising edge of `clock` strictly after
  /// now (n >= 1); n = 0 resumes at the first edge at or after now.
  TimerAwaiter cycles(const ClockDomain& clock, std::uint64_t n, Priority priority = 0);

  /// `co_await sim.advance(d)`: the same outcome as `co_await sim.delay(d)`, with no event when
  /// nothing else can happen until now() + d: no event is queued at or before it, it is within
  /// the run's limit, no stop() or exception is pending, nothing waits for the end of the current
  /// event (a finished process's frame), and no event log or hook is on. Then the process would
  /// be the next to run, at now() + d, so now() moves there and the process goes on in place (no
  /// other process runs in between, so every outcome is the same; the event it skips is neither
  /// counted by events_processed() nor logged). Otherwise it is delay(d).
  TimerAwaiter advance(Time duration, Priority priority = 0) {
    return TimerAwaiter(*this, delay_end(duration), priority, true);
  }
  /// `co_await sim.advance_cycles(clock, n)`: cycles(clock, n) as advance() is delay().
  TimerAwaiter advance_cycles(const ClockDomain& clock, std::uint64_t n, Priority priority = 0) {
    return TimerAwaiter(*this, edge_time(clock, n), priority, true);
  }
  /// advance()'s test: true (and now() set to `when`) when nothing else can happen until `when`.
  bool try_advance_in_place(Time when) {
    if (!running_ || tracing_ || stop_requested_ || after_dispatch_ || when > run_limit_) {
      return false;
    }
    if (queue_.next_time() <= when) return false;
    now_ = when;
    return true;
  }

  /// `co_await sim.join(h)`: same as `co_await h`.
  JoinAwaiter join(ProcessHandle handle) const noexcept { return handle.operator co_await(); }
  /// `co_await sim.all_of({e1, e2})`: wait until each event has been notified (at once for an
  /// empty list).
  AllOfAwaiter all_of(EventList events);
  /// `std::size_t i = co_await sim.any_of({e1, e2})`: wait for the first notification of any of
  /// the events; yields its index. Throws std::invalid_argument for an empty list.
  AnyOfAwaiter any_of(EventList events);

  /// Runs until no event is pending (or stop() is called). Rethrows the first exception that
  /// escapes a spawned process, right after the event that raised it; the simulator stays usable.
  void run();
  /// Runs every event with time <= `until`, then sets now() to `until` (unless stopped or an
  /// exception escaped). Throws std::invalid_argument if `until` < now().
  void run_until(Time until);
  /// The latest time t (>= now()) up to which nothing else can happen in the current run: the
  /// earliest queued event is after t, t is within the run's limit, no stop() is pending and no
  /// event log or hook is on; now() when there is none or outside a run. The running process may
  /// then go on as if it had waited until any time up to t (`co_await delay_until(t)`) without
  /// that event: no other process runs in between, so every outcome is the same (the event it
  /// skips is neither counted nor logged).
  Time quiet_horizon() {
    if (!running_ || tracing_ || stop_requested_) return now_;
    const Time next = queue_.next_time();  // >= now_
    return next <= now_ ? now_ : std::min(run_limit_, next - 1);
  }
  /// Makes the current run()/run_until() return after the event being processed.
  void stop() noexcept {
    stop_requested_ = true;
    after_dispatch_ = true;
  }

  /// Records every processed event into event_log() from now on (off by default; costs one flag
  /// test per event when off).
  void enable_event_log(bool enabled = true);
  /// Events recorded since enable_event_log().
  const std::vector<EventRecord>& event_log() const noexcept { return event_log_; }
  /// Calls `hook` for every processed event (pass {} to remove).
  void set_event_hook(std::function<void(const EventRecord&)> hook);

  /// Schedules `handle` to resume at `when` (>= now()). Used by awaiters; `process` labels the
  /// event in the log.
  void schedule_resume(Time when, Priority priority, std::coroutine_handle<> handle,
                       detail::ProcessRecord* process) {
    schedule(when, priority, handle.address(), process, nullptr);
  }
  /// Schedules the coroutine waiting in `node` to resume now (used by Event, Resource, Fifo).
  void wake(const detail::WaiterNode& node, Priority priority = 0) {
    schedule(now_, priority, node.handle.address(), node.process, nullptr);
  }
  /// Schedules a timed notification of `event` at `when` (used by Event::notify_at).
  void schedule_notification(Time when, Priority priority, Event& event);
  /// Drops pending timed notifications of `event` (used by ~Event).
  void cancel_notifications(const Event& event);
  /// True while the destructor tears down suspended processes.
  bool shutting_down() const noexcept { return shutting_down_; }

 private:
  friend void detail::finish_process(detail::ProcessRecord*, std::exception_ptr,
                                     std::coroutine_handle<>) noexcept;

  struct Label {
    detail::ProcessRecord* process = nullptr;
    const Event* event = nullptr;
  };

  static constexpr std::uint64_t kSequenceLimit = std::uint64_t{1} << 48;

  /// now() + duration; throws TimeRangeError when that reaches kTimeMax (delay's check).
  Time delay_end(Time duration) const {
    if (duration >= kTimeMax - now_) [[unlikely]] {
      throw_time_overflow(duration);
    }
    return now_ + duration;
  }
  /// The time cycles(clock, n) resumes at; throws TimeRangeError at kTimeMax. Edge k =
  /// cycles_in(now) is the last edge at or before now; the n-th edge after now is k + n.
  Time edge_time(const ClockDomain& clock, std::uint64_t n) const {
    const Time when =
        n == 0 ? clock.next_edge(now_) : clock.time_of_cycles(clock.cycles_in(now_) + n);
    if (when == kTimeMax) [[unlikely]] {
      throw_reserved_edge();
    }
    return when;
  }
  [[noreturn]] static void throw_reserved_edge();

  void schedule(Time when, Priority priority, void* target, detail::ProcessRecord* process,
                const Event* event) {
    const std::uint64_t sequence = next_sequence_++;
    if (sequence >= kSequenceLimit || when == kTimeMax) [[unlikely]] {
      throw_schedule_error(when);
    }
    queue_.push(QueueEntry{when, pack_order(priority, sequence), target});
    if (tracing_) [[unlikely]] {
      labels_[sequence] = Label{process, event};
    }
  }

  void run_loop(Time limit);
  void after_dispatch();
  void record_event(const QueueEntry& entry);
  void retire(detail::ProcessRecord* record, std::exception_ptr error,
              std::coroutine_handle<> frame) noexcept;
  [[noreturn]] void throw_time_overflow(Time duration) const;
  [[noreturn]] void throw_schedule_error(Time when);

  Time now_ = 0;
  Time run_limit_ = 0;  ///< the current run's last time (run_until's; kTimeMax for run())
  std::uint64_t events_processed_ = 0;
  std::uint64_t next_sequence_ = 0;
  EventQueue queue_;

  bool running_ = false;
  bool after_dispatch_ = false;  ///< something to do after the current event (see after_dispatch)
  bool stop_requested_ = false;
  bool shutting_down_ = false;
  std::exception_ptr pending_exception_;
  std::vector<std::coroutine_handle<>> finished_frames_;  ///< destroyed after the event

  std::deque<detail::ProcessRecord> records_;
  std::vector<detail::ProcessRecord*> free_records_;
  std::uint64_t next_process_id_ = 0;
  std::size_t live_processes_ = 0;

  bool tracing_ = false;  ///< event log or hook active
  bool log_enabled_ = false;
  std::vector<EventRecord> event_log_;
  std::function<void(const EventRecord&)> hook_;
  std::unordered_map<std::uint64_t, Label> labels_;  ///< sequence -> label, only while tracing
};

inline bool TimerAwaiter::await_ready() const {
  return in_place_ && sim_->try_advance_in_place(when_);
}

template <class Promise>
void TimerAwaiter::await_suspend(std::coroutine_handle<Promise> handle) const {
  sim_->schedule_resume(when_, priority_, handle, detail::process_of(handle));
}

}  // namespace edx::sim
