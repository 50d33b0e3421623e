// See real_time_setup.h.
#include "hybridtest/runner/real_time_setup.h"

#include <fmt/core.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <cerrno>
#include <cstring>

#include "hybridtest/common/error.h"
#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

std::unique_ptr<Clock> MakeClock(const std::string& name) {
  if (name.empty() || name == "wall") return std::make_unique<MonotonicClock>();
  if (name == "virtual") return std::make_unique<VirtualClock>();
  throw ConfigError(fmt::format("--clock {}: expected virtual or wall", name));
}

std::vector<std::string> PrepareRealTimeProcess(const io::RealTimeSpec& spec) {
  std::vector<std::string> notes;
  if (spec.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      notes.emplace_back("memory locked (mlockall)");
    } else {
      notes.push_back(fmt::format(
          "memory not locked: mlockall failed ({}); pages may be swapped out during the run. "
          "Allow it with `ulimit -l unlimited` or the capability CAP_IPC_LOCK, or set "
          "real_time.lock_memory: false", std::strerror(errno)));
    }
  }
  if (spec.priority > 0) {
    sched_param param{};
    param.sched_priority = spec.priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (rc == 0) {
      notes.push_back(fmt::format("SCHED_FIFO priority {}", spec.priority));
    } else {
      notes.push_back(fmt::format(
          "SCHED_FIFO priority {} not granted ({}); the loop runs with normal scheduling. Allow "
          "it with the capability CAP_SYS_NICE or an `rtprio` limit in "
          "/etc/security/limits.conf", spec.priority, std::strerror(rc)));
    }
  }
  // The timer slack of a normal thread (50 µs) makes every sleep wake up late; the loop sleeps
  // short and spins the rest (paced_loop.h), and asks for the finest slack.
  if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) == 0) {
    notes.emplace_back("timer slack 1 ns (PR_SET_TIMERSLACK)");
  } else {
    notes.push_back(fmt::format("timer slack not set ({}); sleeps may wake up to 50 µs late",
                                std::strerror(errno)));
  }
  if (spec.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(spec.cpu, &set);
    const int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    notes.push_back(rc == 0 ? fmt::format("pinned to CPU {}", spec.cpu)
                            : fmt::format("not pinned to CPU {} ({}); check `nproc` and the "
                                          "process's cpuset", spec.cpu, std::strerror(rc)));
  }
  return notes;
}

std::unique_ptr<LockFreeObserver> QueueObservers(Session& session, PacedLoop& loop) {
  std::vector<SessionObserver*> kept, queued;
  std::size_t at = 0;
  for (SessionObserver* o : session.ExchangeObservers({})) {
    if (o->real_time_safe()) {
      kept.push_back(o);
    } else {
      if (queued.empty()) at = kept.size();
      queued.push_back(o);
    }
  }
  std::unique_ptr<LockFreeObserver> queue;
  if (!queued.empty()) {
    std::size_t actuators = 0;
    for (const auto& s : session.substructures()) {
      actuators += static_cast<std::size_t>(s->num_actuators());
    }
    queue = std::make_unique<LockFreeObserver>(
        std::move(queued), static_cast<std::size_t>(session.spec().real_time.queue),
        JournalChannels(session.spec()).size(), std::max<std::size_t>(actuators, 1));
    kept.insert(kept.begin() + static_cast<std::ptrdiff_t>(at), queue.get());
    loop.SetQueue(queue.get());
  }
  session.ExchangeObservers(std::move(kept));
  return queue;
}

}  // namespace hybridtest::runner
