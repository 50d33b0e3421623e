#pragma once
// SpscRing: a bounded lock-free queue of one producer and one consumer thread (a ring of
// `capacity` preallocated slots, two atomic indices; Lamport's queue with acquire/release
// ordering). The producer writes into the slot Claim() gives and publishes it with Publish();
// the consumer reads Front() and frees it with Pop(). Nothing allocates after construction and
// neither side ever waits for the other: a full ring makes Claim() return nullptr, and the
// producer decides (a real-time loop stops the test safely rather than wait).
#include <atomic>
#include <cstddef>
#include <vector>

namespace hybridtest::runner {

template <typename T>
class SpscRing {
 public:
  // capacity ≥ 1 slots, each made by `make` (e.g. with its buffers sized).
  template <typename Make>
  SpscRing(std::size_t capacity, Make make) {
    slots_.reserve(capacity + 1);
    for (std::size_t i = 0; i < capacity + 1; ++i) slots_.push_back(make());
  }

  // Producer: the next free slot, or nullptr if the ring is full.
  T* Claim() {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    const std::size_t next = (tail + 1) % slots_.size();
    if (next == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[tail];
  }
  // Producer: makes the claimed slot visible to the consumer.
  void Publish() {
    tail_.store((tail_.load(std::memory_order_relaxed) + 1) % slots_.size(),
                std::memory_order_release);
  }
  // Consumer: the oldest published slot, or nullptr if empty.
  T* Front() {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[head];
  }
  // Consumer: frees the slot Front() gave.
  void Pop() {
    head_.store((head_.load(std::memory_order_relaxed) + 1) % slots_.size(),
                std::memory_order_release);
  }
  bool empty() const {
    return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
  }
  std::size_t capacity() const { return slots_.size() - 1; }
  // Producer: slots Claim() can still give (the consumer may free more meanwhile).
  std::size_t free_slots() const {
    const std::size_t n = slots_.size();
    const std::size_t used = (tail_.load(std::memory_order_relaxed) + n -
                              head_.load(std::memory_order_acquire)) % n;
    return n - 1 - used;
  }

 private:
  std::vector<T> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};  // next slot to read (consumer)
  alignas(64) std::atomic<std::size_t> tail_{0};  // next slot to write (producer)
};

}  // namespace hybridtest::runner
