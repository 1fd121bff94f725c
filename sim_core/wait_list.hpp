#pragma once
// Intrusive FIFO lists of suspended coroutines. A WaiterNode lives inside the awaiter of the
// suspended coroutine (its frame keeps it alive while suspended), so waiting never allocates.
#include <coroutine>
#include <cstddef>

namespace edx::sim {
class Simulator;
}

namespace edx::sim::detail {

struct ProcessRecord;
class CompositeWait;
class WaitList;

/// One suspended coroutine waiting in a WaitList.
struct WaiterNode {
  WaiterNode* prev = nullptr;
  WaiterNode* next = nullptr;
  WaitList* list = nullptr;            ///< the list holding this node, or nullptr
  std::coroutine_handle<> handle;      ///< what to resume
  ProcessRecord* process = nullptr;    ///< owning process (for the event log only)
  CompositeWait* composite = nullptr;  ///< set for members of all_of / any_of waits
  std::size_t index = 0;               ///< position inside a composite wait
};

/// Doubly linked FIFO of WaiterNodes: O(1) append, pop and unlink.
class WaitList {
 public:
  WaitList() = default;
  WaitList(const WaitList&) = delete;
  WaitList& operator=(const WaitList&) = delete;

  /// True when nobody waits.
  bool empty() const noexcept { return head_ == nullptr; }
  /// Number of waiting nodes.
  std::size_t size() const noexcept { return size_; }
  /// The oldest waiter (undefined when empty).
  WaiterNode* front() const noexcept { return head_; }

  /// Appends `node` (which must not be in any list).
  void push_back(WaiterNode* node) noexcept {
    node->prev = tail_;
    node->next = nullptr;
    node->list = this;
    if (tail_ != nullptr) {
      tail_->next = node;
    } else {
      head_ = node;
    }
    tail_ = node;
    ++size_;
  }

  /// Removes and returns the oldest waiter (nullptr when empty).
  WaiterNode* pop_front() noexcept {
    WaiterNode* node = head_;
    if (node != nullptr) remove(node);
    return node;
  }

  /// Unlinks `node`, which must be in this list.
  void remove(WaiterNode* node) noexcept {
    (node->prev != nullptr ? node->prev->next : head_) = node->next;
    (node->next != nullptr ? node->next->prev : tail_) = node->prev;
    node->prev = node->next = nullptr;
    node->list = nullptr;
    --size_;
  }

  /// Empties the list and returns its nodes as a chain linked by `next` (oldest first); every
  /// node's `list` is cleared first so that callbacks may safely unlink other nodes.
  WaiterNode* take_all() noexcept {
    WaiterNode* chain = head_;
    for (WaiterNode* node = chain; node != nullptr; node = node->next) node->list = nullptr;
    head_ = tail_ = nullptr;
    size_ = 0;
    return chain;
  }

  /// Forgets all nodes without touching them (used when a node's owner is gone).
  void clear_links() noexcept {
    for (WaiterNode* node = head_; node != nullptr; node = node->next) node->list = nullptr;
    head_ = tail_ = nullptr;
    size_ = 0;
  }

 private:
  WaiterNode* head_ = nullptr;
  WaiterNode* tail_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace edx::sim::detail
