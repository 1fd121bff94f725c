#include "sim_core/event_queue.hpp"

namespace edx::sim {

void EventQueue::refill() {
  // Precondition: near_ is empty and size_ > 0, so the wheel is active and holds the rest.
  for (;;) {
    if (wheel_count_ > 0) {
      // The next occupied bucket, scanning the bitmap circularly from the one at near_end_.
      const std::size_t buckets = heads_.size();
      const std::size_t start = slot_of(near_end_);
      std::size_t word = start >> 6;
      std::uint64_t bits = occupied_[word] & (~std::uint64_t{0} << (start & 63));
      while (bits == 0) {
        word = (word + 1) & (occupied_.size() - 1);
        bits = occupied_[word];
      }
      const std::size_t slot = (word << 6) + static_cast<std::size_t>(std::countr_zero(bits));
      const std::size_t distance = (slot - start) & (buckets - 1);
      // Bucket `slot` covers [near_end_ + distance W, near_end_ + (distance + 1) W).
      const Time advance = static_cast<Time>(distance + 1) << shift_;
      near_end_ = saturating_add(near_end_, advance);
      horizon_ = saturating_add(horizon_, advance);
      clear_bit(slot);
      for (std::uint32_t index = heads_[slot]; index != kNil;) {
        const std::uint32_t next = nodes_[index].next;
        near_.append_unordered(nodes_[index].entry);
        release_node(index);
        --wheel_count_;
        index = next;
      }
      heads_[slot] = kNil;
      near_.heapify();
      pull_far();
      return;
    }
    // Wheel empty: restart the window at the bucket holding far's earliest entry. That entry is
    // below the new horizon (times are < kTimeMax), so pull_far() moves at least it.
    const Time earliest = far_.top().time;
    near_end_ = earliest & ~((Time{1} << shift_) - 1);
    horizon_ = saturating_add(near_end_, span_);
    pull_far();
  }
}

void EventQueue::pull_far() {
  // Far entries are >= the previous horizon >= near_end_: they belong to the wheel.
  while (!far_.empty() && far_.top().time < horizon_) add_to_wheel(far_.pop());
}

unsigned EventQueue::wanted_bits() const noexcept {
  // About two buckets per pending entry, within [4, max_wheel_bits].
  const auto bits = static_cast<unsigned>(std::bit_width(size_)) + 1;
  return std::clamp(bits, 4u, std::max(4u, tuning_.max_wheel_bits));
}

unsigned EventQueue::wanted_shift(unsigned bits) const noexcept {
  // Smallest b with >= 95% of the sampled recent push delays below 2^b (bin b holds delays of bit
  // width b); then W = 2^b / 2^bits so that the window 2^bits * W covers them.
  std::uint64_t total = 0;
  for (std::uint64_t count : delay_histogram_) total += count;
  const std::uint64_t needed = total - total / 20;
  std::uint64_t cumulative = 0;
  unsigned width = 0;
  for (; width + 1 < kHistogramBins; ++width) {
    cumulative += delay_histogram_[width];
    if (cumulative >= needed) break;
  }
  return width > bits ? width - bits : 0;
}

void EventQueue::adapt() {
  pushes_since_check_ = 0;
  if (!wheel_active()) {
    if (size_ >= tuning_.activate_size) {
      const unsigned bits = wanted_bits();
      rebuild(true, bits, wanted_shift(bits));
    }
  } else if (size_ < tuning_.deactivate_size) {
    rebuild(false, 0, 0);
  } else {
    const unsigned bits = wanted_bits();
    const unsigned shift = wanted_shift(bits);
    const auto current_bits = static_cast<unsigned>(std::countr_zero(heads_.size()));
    // Rebuild only for a change by 4x or more (hysteresis against flapping).
    const auto far_apart = [](unsigned a, unsigned b) { return a + 2 <= b || b + 2 <= a; };
    if (far_apart(bits, current_bits) || far_apart(shift, shift_)) rebuild(true, bits, shift);
  }
  delay_histogram_.fill(0);
  // A multiple of 8, so that the check coincides with a histogram sample.
  check_interval_ = (std::max(tuning_.min_eval_interval, 2 * size_) + 7) & ~std::size_t{7};
}

void EventQueue::rebuild(bool use_wheel, unsigned bits, unsigned shift) {
  scratch_.clear();
  scratch_.reserve(size_);
  near_.drain_into(scratch_);
  far_.drain_into(scratch_);
  for (std::uint32_t& head : heads_) {
    for (std::uint32_t index = head; index != kNil; index = nodes_[index].next) {
      scratch_.push_back(nodes_[index].entry);
    }
    head = kNil;
  }
  nodes_.clear();
  free_node_ = kNil;
  wheel_count_ = 0;
  if (use_wheel) {
    const std::size_t buckets = std::size_t{1} << bits;
    heads_.assign(buckets, kNil);
    occupied_.assign((buckets + 63) / 64, 0);
    // Keep the window span 2^bits * W <= 2^63 so that window arithmetic cannot overflow.
    shift_ = std::min(shift, 63u - bits);
    span_ = static_cast<Time>(buckets) << shift_;
    // All pending entries are at or after the last pop, so none falls below near_end_.
    near_end_ = last_pop_time_ & ~((Time{1} << shift_) - 1);
    horizon_ = saturating_add(near_end_, span_);
  } else {
    heads_ = {};
    occupied_ = {};
    nodes_ = {};
    near_end_ = horizon_ = kTimeMax;
  }
  for (const QueueEntry& entry : scratch_) place(entry);
}

}  // namespace edx::sim
