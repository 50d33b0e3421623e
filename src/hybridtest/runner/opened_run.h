#pragma once
// OpenedRun: what the front door (runner/open_run.h: OpenRun, OpenResume) gives a run it opened
// for writing: the run's lock, and the journal it was opened for. A file-backed Session is made
// from one only (session.h), so that no run writes its files without the lock, the output
// guards, the disk budget and the input record. Only the front door makes a locked one.
#include <optional>
#include <string>

#include "hybridtest/io/run_lock.h"

namespace hybridtest::runner {

struct OpenedRunAccess;  // the front door's (open_run.cc)

// Released, and the lock file removed, when destroyed (or when the Session holding it is).
class OpenedRun {
 public:
  // A run in memory: nothing opened, no lock.
  OpenedRun() = default;
  bool locked() const { return lock_.has_value(); }
  // The journal the run was opened for; "" for a run in memory.
  const std::string& journal() const { return journal_; }

 private:
  friend struct OpenedRunAccess;
  OpenedRun(io::RunLock lock, std::string journal)
      : lock_(std::in_place, std::move(lock)), journal_(std::move(journal)) {}

  std::optional<io::RunLock> lock_;
  std::string journal_;
};

}  // namespace hybridtest::runner
