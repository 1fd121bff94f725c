#include "sim_core/resource.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace edx::sim {

Lease::Lease(Resource* resource) noexcept : resource_(resource), sim_(resource->sim_) {}

Lease::Lease(Lease&& other) noexcept
    : resource_(std::exchange(other.resource_, nullptr)),
      sim_(std::exchange(other.sim_, nullptr)) {}

Lease& Lease::operator=(Lease&& other) noexcept {
  if (this != &other) {
    release();
    resource_ = std::exchange(other.resource_, nullptr);
    sim_ = std::exchange(other.sim_, nullptr);
  }
  return *this;
}

void Lease::release() noexcept {
  if (resource_ == nullptr) return;
  Resource* resource = std::exchange(resource_, nullptr);
  // While the simulator tears down suspended processes the resource may already be gone.
  if (!sim_->shutting_down()) resource->release_unit();
}

bool AcquireAwaiter::await_ready() noexcept { return resource_->try_take(); }

void AcquireAwaiter::enqueue() noexcept { resource_->enqueue(&node_); }

Lease AcquireAwaiter::await_resume() noexcept { return Lease(resource_); }

Resource::Resource(Simulator& sim, std::size_t capacity, std::string name)
    : sim_(&sim), name_(std::move(name)), capacity_(capacity), busy_(sim), queue_(sim) {
  if (capacity == 0) {
    throw std::invalid_argument("edx::sim::Resource '" + name_ + "': capacity must be >= 1");
  }
}

Lease Resource::try_acquire() noexcept { return try_take() ? Lease(this) : Lease(); }

void Resource::book_idle(const Use* uses, std::size_t count) {
  if (count == 0) return;
  bool ok =
      capacity_ == 1 && in_use_ == 0 && waiters_.empty() && uses[0].request <= uses[0].release;
  Time grant = uses[0].request;  // of the previous use
  for (std::size_t i = 1; ok && i < count; ++i) {
    // At most one waiter: asked for once the previous use was granted.
    ok = uses[i].request >= grant && uses[i].request <= uses[i].release &&
         uses[i].release >= uses[i - 1].release;
    grant = std::max(uses[i].request, uses[i - 1].release);
  }
  // Between the statistics' last changes and now.
  ok = ok && uses[count - 1].release <= sim_->now() && busy_.last_change() <= uses[0].request &&
       queue_.last_change() <= uses[0].request;
  if (!ok) {
    throw std::logic_error("edx::sim::Resource '" + name_ +
                           "'::book_idle: expected an idle unit and ordered uses up to now");
  }
  // Each step as acquire()/release_unit() makes it: take at the request, or wait and be handed
  // the unit at the previous release.
  acquisitions_ += count;
  busy_.set_at(uses[0].request, 1.0);
  for (std::size_t i = 1; i < count; ++i) {
    if (uses[i].request < uses[i - 1].release) {
      queue_.set_at(uses[i].request, 1.0);
      queue_.set_at(uses[i - 1].release, 0.0);
    } else {
      busy_.set_at(uses[i - 1].release, 0.0);
      busy_.set_at(uses[i].request, 1.0);
    }
  }
  busy_.set_at(uses[count - 1].release, 0.0);
}

bool Resource::try_take() noexcept {
  if (in_use_ == capacity_ || !waiters_.empty()) return false;
  ++in_use_;
  ++acquisitions_;
  busy_.set(static_cast<double>(in_use_));
  return true;
}

void Resource::enqueue(detail::WaiterNode* node) noexcept {
  waiters_.push_back(node);
  queue_.set(static_cast<double>(waiters_.size()));
}

void Resource::release_unit() noexcept {
  if (detail::WaiterNode* next = waiters_.pop_front()) {
    // Hand the unit straight to the oldest waiter: in_use_ is unchanged.
    ++acquisitions_;
    queue_.set(static_cast<double>(waiters_.size()));
    sim_->wake(*next);
    return;
  }
  --in_use_;
  busy_.set(static_cast<double>(in_use_));
}

}  // namespace edx::sim
