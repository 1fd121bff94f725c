#include "sim_core/simulator.hpp"

#include <stdexcept>
#include <utility>

#include "sim_core/event.hpp"

namespace edx::sim {

namespace detail {
namespace {

constexpr std::size_t kFrameGrain = 64;    ///< bytes of a size class
constexpr std::size_t kFrameClasses = 33;  ///< classes 1..32: frames up to 2 KiB

/// This thread's free frames: heads of intrusive singly linked lists, one per size class.
/// Trivially destructible, so a frame freed while the thread ends still finds them.
thread_local void* free_frames[kFrameClasses] = {};
thread_local bool frames_closed = false;  ///< the lists are gone: free directly

/// Frees the thread's lists when it ends.
struct FrameLists {
  ~FrameLists() {
    frames_closed = true;
    for (void*& head : free_frames) {
      while (head != nullptr) {
        void* next = *static_cast<void**>(head);
        ::operator delete(head);
        head = next;
      }
    }
  }
};
thread_local FrameLists frame_lists;

}  // namespace

void* allocate_frame(std::size_t bytes) {
  const std::size_t c = (bytes + kFrameGrain - 1) / kFrameGrain;
  if (c >= kFrameClasses || frames_closed) return ::operator new(bytes);
  if (void* frame = free_frames[c]) {
    free_frames[c] = *static_cast<void**>(frame);
    return frame;
  }
  return ::operator new(c* kFrameGrain);
}

void free_frame(void* frame, std::size_t bytes) noexcept {
  const std::size_t c = (bytes + kFrameGrain - 1) / kFrameGrain;
  if (c >= kFrameClasses || frames_closed) {
    ::operator delete(frame);
    return;
  }
  (void)&frame_lists;  // its first use registers its destructor: the lists are freed at exit
  *static_cast<void**>(frame) = free_frames[c];
  free_frames[c] = frame;
}

void finish_process(ProcessRecord* record, std::exception_ptr error,
                    std::coroutine_handle<> frame) noexcept {
  record->sim->retire(record, std::move(error), frame);
}

}  // namespace detail

Simulator::~Simulator() {
  shutting_down_ = true;
  for (std::coroutine_handle<> frame : finished_frames_) frame.destroy();
  finished_frames_.clear();
  // Destroy the suspended processes. A frame's destruction also destroys the frames of the
  // subroutine Tasks it is awaiting (they are owned by the awaiting frame).
  for (detail::ProcessRecord& record : records_) {
    if (record.frame) {
      std::coroutine_handle<> frame = std::exchange(record.frame, {});
      record.id = 0;
      frame.destroy();
    }
  }
}

ProcessHandle Simulator::spawn(Process process, std::string name) {
  Process::Handle handle = process.release();
  if (!handle || handle.done()) {
    if (handle) handle.destroy();
    throw std::invalid_argument("edx::sim::Simulator::spawn('" + name +
                                "'): expected a Process that has not run yet");
  }
  if (shutting_down_) {
    handle.destroy();
    return {};
  }
  detail::ProcessRecord* record;
  if (!free_records_.empty()) {
    record = free_records_.back();
    free_records_.pop_back();
  } else {
    record = &records_.emplace_back();
  }
  record->sim = this;
  record->frame = handle;
  record->id = ++next_process_id_;
  // Moved straight into the record (a conditional expression would move it twice).
  if (name.empty()) {
    record->name = "process#" + std::to_string(record->id);
  } else {
    record->name = std::move(name);
  }
  handle.promise().is_root = true;
  handle.promise().process = record;
  ++live_processes_;
  schedule(now_, 0, handle.address(), record, nullptr);
  return ProcessHandle(record, record->id);
}

void Simulator::retire(detail::ProcessRecord* record, std::exception_ptr error,
                       std::coroutine_handle<> frame) noexcept {
  // The frame is suspended at its final point; it is destroyed after the current event (never
  // from inside its own final awaiter).
  record->frame = {};
  record->id = 0;
  --live_processes_;
  for (detail::WaiterNode* node = record->joiners.take_all(); node != nullptr;) {
    detail::WaiterNode* next = node->next;
    wake(*node);
    node = next;
  }
  finished_frames_.push_back(frame);
  free_records_.push_back(record);
  if (error && !pending_exception_) pending_exception_ = std::move(error);
  after_dispatch_ = true;
}

TimerAwaiter Simulator::delay_until(Time when, Priority priority) {
  if (when == kTimeMax) {
    throw TimeRangeError("edx::sim::Simulator::delay_until(kTimeMax): time is reserved");
  }
  if (when < now_) {
    throw std::invalid_argument("edx::sim::Simulator::delay_until(" + std::to_string(when) +
                                " ps) lies before now (" + std::to_string(now_) + " ps)");
  }
  return TimerAwaiter(*this, when, priority);
}

TimerAwaiter Simulator::cycles(const ClockDomain& clock, std::uint64_t n, Priority priority) {
  return TimerAwaiter(*this, edge_time(clock, n), priority);
}

void Simulator::throw_reserved_edge() {
  throw TimeRangeError("edx::sim::Simulator::cycles: edge lies at the reserved kTimeMax");
}

void Simulator::run() { run_loop(kTimeMax); }

void Simulator::run_until(Time until) {
  if (until < now_) {
    throw std::invalid_argument("edx::sim::Simulator::run_until(" + std::to_string(until) +
                                " ps) lies before now (" + std::to_string(now_) + " ps)");
  }
  run_loop(until);
  if (!stop_requested_) now_ = until;
  stop_requested_ = false;
}

void Simulator::run_loop(Time limit) {
  if (running_) throw std::logic_error("edx::sim::Simulator::run called from inside a process");
  struct RunningGuard {
    Simulator& sim;
    explicit RunningGuard(Simulator& s) : sim(s) { sim.running_ = true; }
    ~RunningGuard() { sim.running_ = false; }
  } guard(*this);
  stop_requested_ = false;
  after_dispatch_ = false;
  run_limit_ = limit;
  QueueEntry entry;
  while (queue_.pop_not_after(limit, entry)) {
    now_ = entry.time;
    ++events_processed_;
    if (tracing_) [[unlikely]] {
      record_event(entry);
    }
    const auto bits = reinterpret_cast<std::uintptr_t>(entry.target);
    if ((bits & 1u) != 0) [[unlikely]] {
      reinterpret_cast<Event*>(bits & ~std::uintptr_t{1})->fire_scheduled(entry.priority());
    } else {
      std::coroutine_handle<>::from_address(entry.target).resume();
    }
    if (after_dispatch_) [[unlikely]] {
      after_dispatch();
      if (stop_requested_) break;
    }
  }
}

void Simulator::after_dispatch() {
  after_dispatch_ = false;
  for (std::coroutine_handle<> frame : finished_frames_) frame.destroy();
  finished_frames_.clear();
  if (pending_exception_) std::rethrow_exception(std::exchange(pending_exception_, nullptr));
}

void Simulator::schedule_notification(Time when, Priority priority, Event& event) {
  const auto bits = reinterpret_cast<std::uintptr_t>(&event) | 1u;
  schedule(when, priority, reinterpret_cast<void*>(bits), nullptr, &event);
}

void Simulator::cancel_notifications(const Event& event) {
  const auto tagged = reinterpret_cast<std::uintptr_t>(&event) | 1u;
  queue_.remove_if([tagged, this](const QueueEntry& entry) {
    if (reinterpret_cast<std::uintptr_t>(entry.target) != tagged) return false;
    labels_.erase(entry.sequence());
    return true;
  });
}

void Simulator::enable_event_log(bool enabled) {
  log_enabled_ = enabled;
  tracing_ = log_enabled_ || static_cast<bool>(hook_);
  if (!tracing_) labels_.clear();
}

void Simulator::set_event_hook(std::function<void(const EventRecord&)> hook) {
  hook_ = std::move(hook);
  tracing_ = log_enabled_ || static_cast<bool>(hook_);
  if (!tracing_) labels_.clear();
}

void Simulator::record_event(const QueueEntry& entry) {
  EventRecord record;
  record.time = entry.time;
  record.priority = entry.priority();
  record.sequence = entry.sequence();
  const auto found = labels_.find(record.sequence);
  if (found != labels_.end()) {
    const Label label = found->second;
    labels_.erase(found);
    if (label.event != nullptr) {
      record.kind = EventRecord::Kind::kNotify;
      record.name = label.event->name();
    } else if (label.process != nullptr) {
      record.process_id = label.process->id;
      record.name = label.process->name;
    }
  }
  if (hook_) hook_(record);
  if (log_enabled_) event_log_.push_back(std::move(record));
}

void Simulator::throw_time_overflow(Time duration) const {
  throw TimeRangeError("edx::sim::Simulator::delay(" + std::to_string(duration) + " ps) at " +
                       std::to_string(now_) + " ps lies beyond the largest representable time");
}

void Simulator::throw_schedule_error(Time when) {
  if (when == kTimeMax) {
    throw TimeRangeError("edx::sim::Simulator: cannot schedule at kTimeMax (reserved)");
  }
  throw EventCountError("more than 2^48 events scheduled in one simulation");
}

}  // namespace edx::sim
