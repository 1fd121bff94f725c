#include "sim_core/event.hpp"

#include <stdexcept>
#include <utility>

namespace edx::sim {

void EventAwaiter::enqueue() noexcept { event_->waiters_.push_back(&node_); }

Event::Event(Simulator& sim, std::string name) : sim_(&sim), name_(std::move(name)) {}

Event::~Event() {
  // During simulator teardown the waiting frames may already be gone: touch nothing.
  if (sim_->shutting_down()) return;
  if (pending_timed_ > 0) sim_->cancel_notifications(*this);
  waiters_.clear_links();
}

void Event::notify(Priority priority) { fire(priority); }

void Event::notify_at(Time when, Priority priority) {
  if (when < sim_->now()) {
    throw std::invalid_argument("edx::sim::Event '" + name_ + "': notify_at(" +
                                std::to_string(when) + " ps) lies before now (" +
                                std::to_string(sim_->now()) + " ps)");
  }
  sim_->schedule_notification(when, priority, *this);
  ++pending_timed_;
}

void Event::notify_after(Time delay, Priority priority) {
  if (delay > kTimeMax - sim_->now()) {
    throw TimeRangeError("edx::sim::Event '" + name_ + "': notify_after(" + std::to_string(delay) +
                         " ps) lies beyond the largest time");
  }
  notify_at(sim_->now() + delay, priority);
}

void Event::fire_scheduled(Priority priority) {
  --pending_timed_;
  fire(priority);
}

void Event::fire(Priority priority) {
  ++notifications_;
  // Detach the current waiters first: coroutines that wait again after resuming wait for the
  // next notification, and composite waits may unlink their other members meanwhile.
  for (detail::WaiterNode* node = waiters_.take_all(); node != nullptr;) {
    detail::WaiterNode* next = node->next;
    node->prev = node->next = nullptr;
    if (node->composite == nullptr) {
      sim_->wake(*node, priority);
    } else {
      node->composite->member_fired(*node, priority);
    }
    node = next;
  }
}

namespace detail {

CompositeWait::CompositeWait(Simulator& sim, std::vector<Event*> events, bool wait_for_any)
    : sim_(&sim), events_(std::move(events)), wait_for_any_(wait_for_any) {
  for (const Event* event : events_) {
    if (event == nullptr) throw std::invalid_argument("edx::sim: all_of/any_of given a null Event");
  }
  if (wait_for_any_ && events_.empty()) {
    throw std::invalid_argument("edx::sim::Simulator::any_of: expected at least one event");
  }
}

void CompositeWait::suspend(std::coroutine_handle<> handle, ProcessRecord* process) {
  handle_ = handle;
  process_ = process;
  remaining_ = events_.size();
  nodes_.resize(events_.size());  // sized once: nodes must not move while linked
  for (std::size_t i = 0; i < events_.size(); ++i) {
    WaiterNode& node = nodes_[i];
    node.handle = handle;
    node.process = process;
    node.composite = this;
    node.index = i;
    events_[i]->waiters_.push_back(&node);
  }
}

void CompositeWait::member_fired(WaiterNode& node, Priority priority) {
  if (finished_) return;
  if (wait_for_any_) {
    finished_ = true;
    fired_index_ = node.index;
    for (WaiterNode& other : nodes_) {
      if (other.list != nullptr) other.list->remove(&other);
    }
  } else if (--remaining_ > 0) {
    return;
  } else {
    finished_ = true;
  }
  sim_->schedule_resume(sim_->now(), priority, handle_, process_);
}

}  // namespace detail

AllOfAwaiter Simulator::all_of(EventList events) {
  return AllOfAwaiter(*this, std::move(events.events()), false);
}

AnyOfAwaiter Simulator::any_of(EventList events) {
  return AnyOfAwaiter(*this, std::move(events.events()), true);
}

}  // namespace edx::sim
