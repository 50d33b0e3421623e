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
  // The absolute deadline on CLOCK_MONOTONIC: origin + t.
  const double whole = std::floor(t);
  long sec = origin_s_ + static_cast<long>(whole);
  long nsec = origin_ns_ + static_cast<long>(std::llround((t - whole) * 1e9));
  while (nsec >= 1000000000L) {
    nsec -= 1000000000L;
    ++sec;
  }
  const timespec deadline{sec, nsec};
  // Restarted after a signal: the deadline is absolute, so nothing drifts.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

}  // namespace hybridtest
