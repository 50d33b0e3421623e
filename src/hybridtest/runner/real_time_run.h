#pragma once
// RealTimeRun: the real-time setting of a `hybridtest run` (docs/real-time.md, decision 0016):
// chooses the clock (`--clock virtual|wall`; wall by default), checks the delay stability of
// every slot before anything moves, prepares the process for a wall-clock run (mlockall,
// SCHED_FIFO priority, CPU affinity and a 1 ns timer slack, each with a clear message where the
// system does not permit it), and sets a PacedLoop as the session's pacer. Run() is the
// session's one loop (Session::Run), paced or not: the monitor's Hold/Continue/Stop act through
// the same path on every run.
// The stepping thread writes no file: every observer that is not real_time_safe() (the run's
// files, the progress display, ...) is put behind one LockFreeObserver of `real_time.queue`
// events, drained on a thread of its own; the loop holds the run before that queue fills.
// For a config without the block it is disabled (and refuses a --clock, which would mean
// nothing there).
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

class RealTimeRun {
 public:
  // Adds the paced loop to the session's observers (before Initialize()). Throws ConfigError
  // for a --clock without a `real_time:` block and for a scheme that cannot run paced.
  RealTimeRun(Session& session, const std::string& clock, bool quiet);
  bool enabled() const { return loop_ != nullptr; }
  // Session::Run(), paced when enabled().
  StepResult Run();
  const PacedLoop* loop() const { return loop_.get(); }
  // The queue in front of the other observers (null before Run()).
  const LockFreeObserver* queue() const { return queue_.get(); }

 private:
  Session& session_;
  bool quiet_;
  std::unique_ptr<Clock> clock_;
  std::unique_ptr<PacedLoop> loop_;
  std::unique_ptr<LockFreeObserver> queue_;
};

}  // namespace hybridtest::runner
