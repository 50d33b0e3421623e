// See clock.h.
#include "hybridtest/common/clock.h"

#include <cerrno>
#include <cmath>
#include <ctime>

namespace hybridtest {

MonotonicClock::MonotonicClock() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  origin_s_ = ts.tv_sec;
  origin_ns_ = ts.tv_nsec;
}

double MonotonicClock::Now() const {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec - origin_s_) +
         1e-9 * static_cast<double>(ts.tv_nsec - origin_ns_);
}

void MonotonicClock::WaitUntil(double t) {
  // Sleep to kSpinBeforeDeadline before t, then spin the rest: a sleep wakes up late by the
  // thread's timer slack (50 µs by default), a spin does not.
  const double wake = t - kSpinBeforeDeadline;
  // The absolute wake-up on CLOCK_MONOTONIC: origin + wake.
  const double whole = std::floor(wake);
  long sec = origin_s_ + static_cast<long>(whole);
  long nsec = origin_ns_ + static_cast<long>(std::llround((wake - whole) * 1e9));
  while (nsec >= 1000000000L) {
    nsec -= 1000000000L;
    ++sec;
  }
  while (nsec < 0) {
    nsec += 1000000000L;
    --sec;
  }
  const timespec deadline{sec, nsec};
  // Restarted after a signal: the deadline is absolute, so nothing drifts.
  if (Now() < wake) {
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
    }
  }
  while (Now() < t) {
  }
}

}  // namespace hybridtest
