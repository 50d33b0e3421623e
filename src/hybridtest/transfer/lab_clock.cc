#include "hybridtest/transfer/lab_clock.h"

#include <thread>

namespace hybridtest::transfer {

void LabClock::Start() {
  if (started_) return;
  started_ = true;
  origin_ = std::chrono::steady_clock::now();
}

void LabClock::Pace() const {
  if (!realtime_ || !started_) return;
  const auto due = origin_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(lab_time_));
  std::this_thread::sleep_until(due);
}

}  // namespace hybridtest::transfer
