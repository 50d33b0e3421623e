// See background_thread.h.
#include "hybridtest/monitor/background_thread.h"

#include <fmt/core.h>
#include <pthread.h>
#include <sched.h>

#include <cstring>

namespace hybridtest::monitor {

std::string MoveThisThreadToBackground(int avoid_cpu) {
  std::string note;
  sched_param param{};
  param.sched_priority = 0;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);
  note = rc == 0 ? "SCHED_IDLE" : fmt::format("SCHED_IDLE refused ({})", std::strerror(rc));
  cpu_set_t set;
  CPU_ZERO(&set);
  if (avoid_cpu >= 0 && avoid_cpu < CPU_SETSIZE &&
      pthread_getaffinity_np(pthread_self(), sizeof set, &set) == 0 &&
      CPU_ISSET(avoid_cpu, &set) && CPU_COUNT(&set) > 1) {
    CPU_CLR(avoid_cpu, &set);
    const int arc = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    note += arc == 0 ? fmt::format(", off CPU {}", avoid_cpu)
                     : fmt::format(", not moved off CPU {} ({})", avoid_cpu,
                                   std::strerror(arc));
  }
  return note;
}

}  // namespace hybridtest::monitor
