#pragma once
// The pending-event set, ordered exactly by (time, priority, insertion sequence).
//
// Entries are 24-byte PODs; no allocation per event once the containers have grown to the
// model's working size; no virtual calls, no std::function.
//
// Structure (a timing wheel in front of a heap, after calendar/ladder queues):
//   near   4-ary min-heap of the entries with time <  near_end
//   wheel  2^bits buckets of width W = 2^shift ps covering [near_end, horizon),
//          horizon = near_end + 2^bits * W; each bucket an unsorted singly linked list of
//          nodes from one pooled array (recycled LIFO, so pushes touch warm memory), plus an
//          occupancy bitmap to skip empty buckets
//   far    4-ary min-heap of the entries with time >= horizon
// Every near entry precedes every wheel entry, which precedes every far entry, so the near
// heap's top is the global minimum (ties at equal time are always in the same container and are
// ordered there by (priority, sequence)). When near runs dry, the next occupied bucket becomes
// the near heap and the wheel window slides forward, pulling far entries into it. A push usually
// costs an append to a bucket and a pop a sift in a heap of a handful of entries, instead of a
// sift through log4(n) levels of one big heap.
//
// Small queues (< activate_size entries) use the near heap alone (near_end = horizon = kTimeMax).
// The wheel adapts: 2^bits ~ 2n buckets (n pending entries), and a log2 histogram of push delays
// picks W so that 95% of pushes land inside the window; the queue is rebuilt (O(n)) only when
// W or the bucket count should change by >= 4x, checked every max(min_eval_interval, 2n)
// pushes, so rebuilds cost O(1) amortized per push.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim_core/time.hpp"

namespace edx::sim {

/// Tie-break between events at the same time: the smaller priority runs first; equal priorities
/// run in insertion order. Default 0.
using Priority = std::int16_t;

/// One scheduled event. `order` packs the biased priority (top 16 bits) and the insertion
/// sequence number (low 48 bits), so (time, order) compares exactly as (time, priority, seq).
struct QueueEntry {
  Time time;
  std::uint64_t order;
  void* target;  ///< coroutine frame address, or a tagged Event* (low bit set)

  /// Priority encoded in `order`.
  Priority priority() const noexcept {
    return static_cast<Priority>(static_cast<std::uint16_t>(order >> 48) ^ 0x8000u);
  }
  /// Insertion sequence number encoded in `order`.
  std::uint64_t sequence() const noexcept { return order & ((std::uint64_t{1} << 48) - 1); }
};

/// Packs (priority, sequence) into QueueEntry::order (sequence must be < 2^48).
constexpr std::uint64_t pack_order(Priority priority, std::uint64_t sequence) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint16_t>(priority) ^ 0x8000u) << 48) |
         sequence;
}

/// Strict order of entries: by time, then priority, then insertion.
inline bool runs_before(const QueueEntry& a, const QueueEntry& b) noexcept {
  return a.time != b.time ? a.time < b.time : a.order < b.order;
}

namespace detail {

/// 4-ary min-heap of QueueEntry on a std::vector (size == number of entries).
class QuaternaryHeap {
 public:
  bool empty() const noexcept { return items_.empty(); }
  std::size_t size() const noexcept { return items_.size(); }
  const QueueEntry& top() const noexcept { return items_[0]; }

  void push(const QueueEntry& entry) {
    items_.push_back(entry);
    sift_up(items_.size() - 1, entry);
  }

  QueueEntry pop() noexcept {
    const QueueEntry top = items_[0];
    const QueueEntry last = items_.back();
    items_.pop_back();
    if (!items_.empty()) sift_down(0, last);
    return top;
  }

  /// Appends without restoring the heap order; call heapify() afterwards.
  void append_unordered(const QueueEntry& entry) { items_.push_back(entry); }
  /// Restores the heap order (Floyd's bottom-up construction, O(n)).
  void heapify() noexcept {
    const std::size_t n = items_.size();
    if (n < 2) return;
    for (std::size_t i = (n - 2) / kArity + 1; i-- > 0;) sift_down(i, items_[i]);
  }

  /// Moves all entries to the end of `out`.
  void drain_into(std::vector<QueueEntry>& out) {
    out.insert(out.end(), items_.begin(), items_.end());
    items_.clear();
  }

  /// Removes the entries matching `predicate`; returns how many.
  template <class Predicate>
  std::size_t remove_if(Predicate& predicate) {
    const auto end = std::remove_if(items_.begin(), items_.end(), predicate);
    const auto removed = static_cast<std::size_t>(items_.end() - end);
    items_.erase(end, items_.end());
    heapify();
    return removed;
  }

 private:
  static constexpr std::size_t kArity = 4;

  void sift_up(std::size_t index, QueueEntry entry) noexcept {
    while (index > 0) {
      const std::size_t parent = (index - 1) / kArity;
      if (!runs_before(entry, items_[parent])) break;
      items_[index] = items_[parent];
      index = parent;
    }
    items_[index] = entry;
  }

  void sift_down(std::size_t index, QueueEntry entry) noexcept {
    const std::size_t n = items_.size();
    for (;;) {
      const std::size_t first = index * kArity + 1;
      if (first >= n) break;
      const std::size_t last = first + kArity < n ? first + kArity : n;
      std::size_t best = first;
      for (std::size_t child = first + 1; child < last; ++child) {
        if (runs_before(items_[child], items_[best])) best = child;
      }
      if (!runs_before(items_[best], entry)) break;
      items_[index] = items_[best];
      index = best;
    }
    items_[index] = entry;
  }

  std::vector<QueueEntry> items_;
};

}  // namespace detail

/// The pending-event queue (see the top of event_queue.hpp). Precondition of push(): the entry's
/// time is not before the last popped entry's time (the simulator never schedules in the past)
/// and is below kTimeMax (reserved).
class EventQueue {
 public:
  /// Tuning knobs; the defaults suit models from a few to ~10^5 pending events. Tests shrink
  /// them to exercise every path.
  struct Tuning {
    std::size_t activate_size = 16;        ///< use the wheel from this many pending entries
    std::size_t deactivate_size = 8;       ///< back to a plain heap below this many
    unsigned max_wheel_bits = 14;          ///< at most 2^max_wheel_bits buckets
    std::size_t min_eval_interval = 4096;  ///< pushes between two adaptation checks
  };

  EventQueue() : EventQueue(Tuning{}) {}
  explicit EventQueue(const Tuning& tuning)
      : tuning_(tuning), check_interval_((tuning.min_eval_interval + 7) & ~std::size_t{7}) {}

  /// True when no event is pending.
  bool empty() const noexcept { return size_ == 0; }
  /// Number of pending events.
  std::size_t size() const noexcept { return size_; }
  /// True while the timing wheel is in use (for tests and diagnostics).
  bool wheel_active() const noexcept { return !heads_.empty(); }

  /// Adds an entry.
  void push(const QueueEntry& entry) {
    ++size_;
    // Every 8th push feeds the delay histogram (a sample is enough to size the wheel).
    if ((++pushes_since_check_ & 7) == 0) {
      ++delay_histogram_[std::bit_width(entry.time - last_pop_time_)];
      if (pushes_since_check_ >= check_interval_) [[unlikely]] {
        place(entry);
        adapt();
        return;
      }
    }
    place(entry);
  }

  /// The earliest entry's time; kTimeMax when the queue is empty.
  Time next_time() {
    if (near_.empty()) {
      if (size_ == 0) return kTimeMax;
      refill();
    }
    return near_.top().time;
  }

  /// Removes the earliest entry into `out` and returns true, unless the queue is empty or that
  /// entry's time is after `limit` (then returns false and changes nothing).
  bool pop_not_after(Time limit, QueueEntry& out) {
    if (near_.empty()) {
      if (size_ == 0) return false;
      refill();
    }
    if (near_.top().time > limit) return false;
    out = near_.pop();
    --size_;
    last_pop_time_ = out.time;
    return true;
  }

  /// Removes every entry for which `predicate(entry)` holds (O(n); not for the hot path).
  template <class Predicate>
  std::size_t remove_if(Predicate predicate) {
    std::size_t removed = near_.remove_if(predicate) + far_.remove_if(predicate);
    for (std::size_t slot = 0; slot < heads_.size(); ++slot) {
      for (std::uint32_t* link = &heads_[slot]; *link != kNil;) {
        Node& node = nodes_[*link];
        if (predicate(node.entry)) {
          const std::uint32_t index = *link;
          *link = node.next;
          release_node(index);
          --wheel_count_;
          ++removed;
        } else {
          link = &node.next;
        }
      }
      if (heads_[slot] == kNil) clear_bit(slot);
    }
    size_ -= removed;
    return removed;
  }

 private:
  static constexpr std::size_t kHistogramBins = 65;
  static constexpr std::uint32_t kNil = 0xFFFFFFFFu;

  /// A wheel entry: bucket lists link nodes of nodes_ by index.
  struct Node {
    QueueEntry entry;
    std::uint32_t next;
  };

  static Time saturating_add(Time a, Time b) noexcept {
    return a > kTimeMax - b ? kTimeMax : a + b;
  }

  std::size_t slot_of(Time time) const noexcept {
    return static_cast<std::size_t>(time >> shift_) & (heads_.size() - 1);
  }
  void release_node(std::uint32_t index) noexcept {
    nodes_[index].next = free_node_;
    free_node_ = index;
  }
  /// Prepends `entry` to its bucket's list.
  void add_to_wheel(const QueueEntry& entry) {
    std::uint32_t index = free_node_;
    if (index != kNil) {
      free_node_ = nodes_[index].next;
    } else {
      index = static_cast<std::uint32_t>(nodes_.size());
      nodes_.emplace_back();
    }
    const std::size_t slot = slot_of(entry.time);
    nodes_[index] = Node{entry, heads_[slot]};
    heads_[slot] = index;
    set_bit(slot);
    ++wheel_count_;
  }
  void set_bit(std::size_t slot) noexcept {
    occupied_[slot >> 6] |= std::uint64_t{1} << (slot & 63);
  }
  void clear_bit(std::size_t slot) noexcept {
    occupied_[slot >> 6] &= ~(std::uint64_t{1} << (slot & 63));
  }

  /// Routes an entry to near, wheel or far (size_ already counted).
  [[gnu::always_inline]] void place(const QueueEntry& entry) {
    if (entry.time < near_end_) {
      near_.push(entry);
    } else if (entry.time < horizon_) {
      add_to_wheel(entry);
    } else {
      far_.push(entry);
    }
  }

  void refill();
  void pull_far();
  void adapt();
  void rebuild(bool use_wheel, unsigned bits, unsigned shift);
  unsigned wanted_bits() const noexcept;
  unsigned wanted_shift(unsigned bits) const noexcept;

  Tuning tuning_;
  std::size_t size_ = 0;
  Time last_pop_time_ = 0;

  detail::QuaternaryHeap near_;
  Time near_end_ = kTimeMax;  ///< kTimeMax while the wheel is off: everything lives in near_
  Time horizon_ = kTimeMax;
  unsigned shift_ = 0;
  Time span_ = 0;                        ///< buckets * W
  std::vector<std::uint32_t> heads_;     ///< first node per bucket; empty while the wheel is off
  std::vector<std::uint64_t> occupied_;  ///< bit per non-empty bucket
  std::vector<Node> nodes_;              ///< node pool of all buckets
  std::uint32_t free_node_ = kNil;       ///< free list through Node::next
  std::size_t wheel_count_ = 0;
  detail::QuaternaryHeap far_;

  std::array<std::uint64_t, kHistogramBins> delay_histogram_{};  ///< by bit_width(delay)
  std::size_t pushes_since_check_ = 0;
  std::size_t check_interval_;
  std::vector<QueueEntry> scratch_;  ///< reused by rebuild()
};

}  // namespace edx::sim
