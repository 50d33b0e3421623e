#pragma once
// RunLock: one master per run (docs/safety.md, "One master per run"). `run`, `simulate` and
// `resume` hold an exclusive advisory lock (flock) on "<dir>/<stem>.lock", beside the journal
// "<dir>/<stem>.csv", for their whole life, and take it before they read the run's state or
// touch any of its files. A second process that wants the same run (another resume, a resume
// of a live run, a run with --overwrite over it) is refused with the holder's PID and host.
//
// The kernel releases the lock when the holder exits, however it exits (kill -9 included), so
// a stale lock never blocks a resume. The lock file holds one line naming the holder. Its
// holder removes it before releasing it; a process that locks a file which is no longer the
// one at the lock's name (removed or replaced in between) opens the new one and tries again,
// so removing it never lets two processes hold the run. A process killed by a signal leaves
// the file behind, unlocked. flock is local to one machine: two hosts that share the results
// directory over NFS are not serialised by it (documented in docs/safety.md).
//
// The lock file is one file, and one file can be removed. The journal is locked too: its
// writer (io::Journal) holds an exclusive flock on the journal's own descriptor for its whole
// life, and Acquire takes the same lock on an existing journal (and its staged copy) and holds
// it until it is released, before a resume cuts or a run --overwrite replaces anything. So
// removing the lock file of a live run does not let a second process in: it is refused on the
// journal (ConfigError, exit 2).
//
// The lock file never replaces a file it does not own: a file at the lock's name whose text is
// not a holder's line (a config named "<stem>.lock", say) is refused, never truncated or
// removed.
#include <sys/types.h>

#include <string>
#include <vector>

namespace hybridtest::io {

// "<dir>/<stem>.lock" for the journal "<dir>/<stem>.csv".
std::string RunLockPath(const std::string& csv_path);

class RunLock {
 public:
  // Takes the lock of the run whose journal is csv_path (its directory must exist) for
  // `command` ("run", "simulate", "resume"). Throws ConfigError (exit 2) if another process
  // holds it, naming that process (PID, host, command, since when) and what to do; IoError if
  // the lock file cannot be created or is not a regular file.
  static RunLock Acquire(const std::string& csv_path, const std::string& command);

  RunLock(RunLock&& other) noexcept
      : fd_(other.fd_), journal_fds_(std::move(other.journal_fds_)),
        path_(std::move(other.path_)), remove_(other.remove_) {
    other.fd_ = -1;
    other.journal_fds_.clear();
  }
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;
  ~RunLock();  // removes the lock file and releases the lock

  const std::string& path() const { return path_; }

 private:
  static RunLock Locked(int fd, const std::string& path, const std::string& command);
  RunLock(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  // Locks the journal (and its staged copy) where they exist; throws ConfigError if a live
  // writer holds one.
  void LockJournal(const std::string& csv_path);
  int fd_ = -1;
  std::vector<int> journal_fds_;  // descriptors holding the journal files' flocks
  std::string path_;
  bool remove_ = true;  // false for an empty file found at the lock's name: left in place
};

// The lock a journal's writer holds on its own file (journal.h). Takes an exclusive flock on
// `fd` (open on the journal file at `path`) without waiting. Returns normally if it is taken,
// or if this process already holds that file's lock through a RunLock (a resume: the RunLock
// took it before the journal was cut). Throws ConfigError (exit 2) naming the file if another
// process holds it: a live run writes there.
void LockJournalFile(int fd, const std::string& path);

}  // namespace hybridtest::io
