// See run_lock.h.
#include "hybridtest/io/run_lock.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/io/atomic_file.h"
#include "hybridtest/io/utc_time.h"

namespace hybridtest::io {

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
    fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
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
      return Locked(fd, path, command);
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
  if (fd_ < 0) return;
  // Removed while still held (a process waiting on the old file sees it gone and retries),
  // then released by closing the last descriptor.
  ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace hybridtest::io
