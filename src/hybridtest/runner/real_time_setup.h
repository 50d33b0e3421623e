#pragma once
// The parts of a real-time run's setting that the Session assembles from its spec
// (docs/real-time.md, decision 0016; Session's constructor, Initialize() and Run()):
//   - the clock the spec names (`real_time.clock`, the command line's --clock, Python's
//     clock=): wall (the default) or virtual;
//   - a wall-clock run's process setup (mlockall, SCHED_FIFO priority, CPU affinity and a 1 ns
//     timer slack, each with a clear message where the system does not permit it);
//   - the queue in front of the observers: the stepping thread writes no file, every observer
//     that is not real_time_safe() (the run's files, the progress display, ...) is put behind
//     one LockFreeObserver of `real_time.queue` events, drained on a thread of its own; the
//     loop holds the run before that queue fills.
// Nothing here is called by a front: the command line, Python and campaigns all step the
// Session, which builds its pacer itself.
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/common/clock.h"
#include "hybridtest/runner/lock_free_observer.h"
#include "hybridtest/runner/paced_loop.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::runner {

// "virtual" or "wall" ("" = wall). Throws ConfigError for anything else.
std::unique_ptr<Clock> MakeClock(const std::string& name);

// Applies the wall-clock process settings of `spec`; returns one line per setting, saying
// what was done or why it was not (never throws).
std::vector<std::string> PrepareRealTimeProcess(const io::RealTimeSpec& spec);

// Puts every observer of `session` that is not real_time_safe() behind one LockFreeObserver
// of `real_time.queue` events, in their order and where the first of them was (the run's files
// open first), and gives it to `loop` (PacedLoop::SetQueue). Returns it (null when every
// observer may stay on the stepping thread). Before Initialize().
std::unique_ptr<LockFreeObserver> QueueObservers(Session& session, PacedLoop& loop);

}  // namespace hybridtest::runner
