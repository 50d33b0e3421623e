// See run_lock.h.
#include "hybridtest/io/run_lock.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sys/sysmacros.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <utility>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/utc_time.h"

namespace hybridtest::io {

namespace {

using FileId = std::pair<dev_t, ino_t>;

// The journal files whose flock this process holds through a RunLock.
std::mutex& HeldMutex() {
  static std::mutex m;
  return m;
}
std::set<FileId>& HeldJournals() {
  static std::set<FileId> held;
  return held;
}

// The PID holding a flock on the file (dev, ino), from /proc/locks; 0 if unknown.
long FlockHolder(dev_t dev, ino_t ino) {
  std::ifstream in("/proc/locks");
  std::string line;
  const std::string id = fmt::format("{:02x}:{:02x}:{}", major(dev), minor(dev), ino);
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string number, kind, mode, access, pid, file;
    fields >> number >> kind;
    if (kind == "->") fields >> kind;  // a waiter
    fields >> mode >> access >> pid >> file;
    if (kind == "FLOCK" && file == id) return std::atol(pid.c_str());
  }
  return 0;
}

// Takes the flock; returns false if another open file description holds it.
bool TryFlock(int fd) {
  int rc = 0;
  do {
    rc = ::flock(fd, LOCK_EX | LOCK_NB);
  } while (rc != 0 && errno == EINTR);
  if (rc == 0) return true;
  if (errno == EWOULDBLOCK) return false;
  throw IoError(fmt::format("cannot lock a journal file: {}", OsError()));
}

std::string LiveWriterMessage(const std::string& path, const struct stat& st) {
  const long pid = FlockHolder(st.st_dev, st.st_ino);
  return fmt::format(
      "{}: a live hybridtest process ({}) is writing this journal and holds its lock, although "
      "the run's lock file {} did not stop us: it was removed or replaced while the run was "
      "live. One process at a time may drive a run, and nothing was changed. Wait for that run "
      "to finish, or stop it (Ctrl-C, or kill {}) and then run hybridtest resume on it",
      path, pid > 0 ? fmt::format("pid {}", pid) : std::string("holder unknown"),
      RunLockPath(path), pid > 0 ? std::to_string(pid) : std::string("its PID"));
}

}  // namespace

void LockJournalFile(int fd, const std::string& path) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    throw IoError(fmt::format("{}: cannot read the journal's file status: {}", path, OsError()));
  }
  if (TryFlock(fd)) return;
  {
    const std::lock_guard<std::mutex> guard(HeldMutex());
    if (HeldJournals().count({st.st_dev, st.st_ino}) != 0) return;  // our own RunLock holds it
  }
  throw ConfigError(LiveWriterMessage(path, st));
}

void RunLock::LockJournal(const std::string& csv_path) {
  for (const std::string& path : {csv_path, StagedPath(csv_path)}) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;  // no such file (yet): its writer locks it when it creates it
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd);  // not a journal: the run's output checks refuse it
      continue;
    }
    bool locked = false;
    try {
      locked = TryFlock(fd);
    } catch (...) {
      ::close(fd);
      throw;
    }
    if (!locked) {
      ::close(fd);
      throw ConfigError(LiveWriterMessage(path, st));
    }
    journal_fds_.push_back(fd);
    const std::lock_guard<std::mutex> guard(HeldMutex());
    HeldJournals().insert({st.st_dev, st.st_ino});
  }
}

std::string RunLockPath(const std::string& csv_path) {
  const std::filesystem::path p(csv_path);
  return (p.parent_path() / (p.stem().string() + ".lock")).string();
}

RunLock RunLock::Acquire(const std::string& csv_path, const std::string& command) {
  const std::string path = RunLockPath(csv_path);
  // The holder removes the file when it releases the lock, so the file locked may have been
  // removed (or replaced) between open() and flock(): then it is opened again.
  int fd = -1;
  for (int attempt = 0;; ++attempt) {
    // O_NOFOLLOW: a symlink planted at the lock's name is refused, never followed.
    // Created here, or found: only a file created here or holding a holder's line is ever
    // removed (an empty file someone else made stays).
    bool created = true;
    fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0 && errno == EEXIST) {
      created = false;
      fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
      if (fd < 0 && errno == ENOENT && attempt < 100) continue;  // removed in between
    }
    if (fd < 0) {
      throw IoError(fmt::format("{}: cannot create the run's lock file: {}; the lock file must "
                                "be a regular file in a writable directory", path, OsError()));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd);
      throw IoError(fmt::format("{}: the run's lock file is not a regular file; remove it", path));
    }
    int rc = 0;
    do {
      rc = ::flock(fd, LOCK_EX | LOCK_NB);
    } while (rc != 0 && errno == EINTR);
    if (rc != 0) break;  // held by another process: reported below
    struct stat now {};
    if (::lstat(path.c_str(), &now) == 0 && now.st_ino == st.st_ino && now.st_dev == st.st_dev) {
      // Only a lock file is ever rewritten and removed: anything else at its name (a config
      // called "<stem>.lock") is left as it is.
      std::array<char, 64> head{};
      const ssize_t n = ::pread(fd, head.data(), head.size(), 0);
      if (n > 0 && std::string(head.data(), static_cast<std::size_t>(n)).rfind("pid ", 0) != 0) {
        ::close(fd);
        throw ConfigError(fmt::format(
            "{}: the run {} uses this name for its lock file, but a file that is not a "
            "hybridtest lock file is there (a config or data file?); it was left untouched. "
            "Rename that file, or choose another --out for the run",
            path, csv_path));
      }
      RunLock lock = Locked(fd, path, command);
      lock.remove_ = created || n > 0;
      lock.LockJournal(csv_path);
      return lock;
    }
    ::close(fd);  // locked a file its holder had just removed: try the new one
    if (attempt == 100) {
      throw IoError(fmt::format("{}: the run's lock file keeps being replaced; is another "
                                "program removing it?", path));
    }
  }
  {
    const int error = errno;
    std::array<char, 512> holder{};
    const ssize_t n = ::pread(fd, holder.data(), holder.size() - 1, 0);
    ::close(fd);
    std::string who = n > 0 ? std::string(holder.data(), static_cast<std::size_t>(n)) : "";
    while (!who.empty() && (who.back() == '\n' || who.back() == '\0')) who.pop_back();
    if (error != EWOULDBLOCK) {
      throw IoError(fmt::format("{}: cannot lock the run: {}", path, std::strerror(error)));
    }
    throw ConfigError(fmt::format(
        "{}: the run is in use by another hybridtest process ({}), which holds its lock {}; "
        "one process at a time may drive a run. Wait for it to finish, or stop it (Ctrl-C, or "
        "kill PID on that host) and then run hybridtest resume {}", csv_path,
        who.empty() ? "holder unknown" : who, path, csv_path));
  }
}

RunLock RunLock::Locked(int fd, const std::string& path, const std::string& command) {
  // The holder's line, for the message of a refused second process.
  std::array<char, 256> host{};
  if (::gethostname(host.data(), host.size() - 1) != 0) host[0] = '\0';
  const std::string line = fmt::format("pid {} on host {}, hybridtest {}, since {}\n", ::getpid(),
                                       host.data(), command, UtcNowIso8601());
  if (::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, line.data(), line.size(), 0) != static_cast<ssize_t>(line.size())) {
    // The lock itself is held; only the holder's description could not be written.
  }
  return RunLock(fd, path);
}

RunLock::~RunLock() {
  for (const int fd : journal_fds_) {
    struct stat st {};
    if (::fstat(fd, &st) == 0) {
      const std::lock_guard<std::mutex> guard(HeldMutex());
      HeldJournals().erase({st.st_dev, st.st_ino});
    }
    ::close(fd);
  }
  if (fd_ < 0) return;
  // Removed while still held (a process waiting on the old file sees it gone and retries),
  // then released by closing the last descriptor.
  if (remove_) ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace hybridtest::io
