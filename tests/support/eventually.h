#pragma once
// Waiting for something another thread or process does, without a timed assertion.
#include <chrono>
#include <thread>

namespace hybridtest::test_support {

// Polls `condition` every 10 ms until it holds, bounded: at most 10 s. Returns whether it did.
template <typename Fn>
bool Eventually(Fn&& condition) {
  for (int i = 0; i < 1000; ++i) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return condition();
}

}  // namespace hybridtest::test_support
