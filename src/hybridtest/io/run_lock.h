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
#include <string>

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

  RunLock(RunLock&& other) noexcept : fd_(other.fd_), path_(std::move(other.path_)) {
    other.fd_ = -1;
  }
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;
  ~RunLock();  // removes the lock file and releases the lock

  const std::string& path() const { return path_; }

 private:
  static RunLock Locked(int fd, const std::string& path, const std::string& command);
  RunLock(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
  int fd_ = -1;
  std::string path_;
};

}  // namespace hybridtest::io
