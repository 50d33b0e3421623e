#pragma once
// FrameRing: a bounded single-producer single-consumer queue of fixed-width frames of doubles,
// preallocated. The producer (a run's stepping thread) never waits and never allocates: a
// full ring drops the new frame and counts it. The consumer (the monitor's collector thread)
// drains what is there. Only two atomics are shared; no lock.
#include <atomic>
#include <cstddef>
#include <vector>

namespace hybridtest::monitor {

class FrameRing {
 public:
  // capacity ≥ 1 frames of `width` doubles each.
  FrameRing(std::size_t capacity, std::size_t width)
      : capacity_(capacity < 1 ? 1 : capacity), width_(width), data_(capacity_ * width) {}
  FrameRing(const FrameRing&) = delete;
  FrameRing& operator=(const FrameRing&) = delete;

  std::size_t width() const { return width_; }
  std::size_t capacity() const { return capacity_; }

  // Producer: the frame to fill, or nullptr if the ring is full (the frame is dropped and
  // counted). Commit() publishes the frame filled.
  double* Begin() noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) >= capacity_) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return nullptr;
    }
    return &data_[(tail % capacity_) * width_];
  }
  void Commit() noexcept { tail_.fetch_add(1, std::memory_order_release); }

  // Consumer: calls fn(const double* frame) for every queued frame, oldest first; returns
  // how many.
  template <typename Fn>
  std::size_t Drain(Fn&& fn) {
    std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    const std::size_t n = tail - head;
    for (; head != tail; ++head) fn(&data_[(head % capacity_) * width_]);
    head_.store(head, std::memory_order_release);
    return n;
  }

  long dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::size_t capacity_;
  std::size_t width_;
  std::vector<double> data_;  // (capacity × width)
  alignas(64) std::atomic<std::size_t> head_{0};  // frames consumed
  alignas(64) std::atomic<std::size_t> tail_{0};  // frames produced
  std::atomic<long> dropped_{0};
};

}  // namespace hybridtest::monitor
