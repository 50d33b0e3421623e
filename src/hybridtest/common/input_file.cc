// See input_file.h.
#include "hybridtest/common/input_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "hybridtest/common/error.h"

namespace hybridtest {
namespace {

// "a FIFO", "a directory", ... for a path that exists but is not a regular file.
std::string FileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string ErrnoProblem(int error) {
  if (error == ENOENT) return "no such file";
  return std::strerror(error);
}

// "<what> = '<path>'", or the path alone when `what` is empty.
std::string Where(const std::string& path, std::string_view what) {
  return what.empty() ? path : fmt::format("{} = '{}'", what, path);
}

[[noreturn]] void Refuse(const std::string& path, std::string_view what, std::string_view noun,
                         const std::string& problem, bool exists) {
  if (!exists) {
    throw ConfigError(fmt::format("{}: cannot open this {} ({}); check that it exists (relative "
                                  "paths start at the current directory)",
                                  Where(path, what), noun, problem));
  }
  throw ConfigError(fmt::format("{}: not a regular file ({}); give a {} here", Where(path, what),
                                problem, noun));
}

}  // namespace

std::string RegularFileProblem(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return ErrnoProblem(errno);
  if (!S_ISREG(st.st_mode)) return FileKind(st.st_mode);
  return {};
}

void RequireRegularFile(const std::string& path, std::string_view what,
                        std::string_view expected) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) Refuse(path, what, expected, ErrnoProblem(errno), false);
  if (!S_ISREG(st.st_mode)) Refuse(path, what, expected, FileKind(st.st_mode), true);
}

std::string ReadInputFile(const std::string& path, std::string_view what,
                          std::string_view expected, std::size_t max_bytes) {
  // stat first: a device is never opened (opening one can have effects of its own).
  RequireRegularFile(path, what, expected);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    Refuse(path, what, expected, ErrnoProblem(error), error != ENOENT);
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    Refuse(path, what, expected, FileKind(st.st_mode), true);
  }
  // One byte beyond the bound tells "too large" from "exactly the bound".
  std::string text;
  text.resize(static_cast<std::size_t>(st.st_size) < max_bytes
                  ? static_cast<std::size_t>(st.st_size) + 1
                  : max_bytes + 1);
  std::size_t got = 0;
  while (true) {
    if (got == text.size()) {
      if (got > max_bytes) break;
      text.resize(std::min(max_bytes + 1, text.size() * 2 + 4096));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string error = std::strerror(errno);
      ::close(fd);
      throw ConfigError(fmt::format("{}: cannot read this {} ({}); check its permissions",
                                    Where(path, what), expected, error));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(got);
  if (text.size() > max_bytes) {
    throw ConfigError(fmt::format("{}: larger than {} bytes, the most a {} may hold; check "
                                  "that this is the right file", Where(path, what), max_bytes,
                                  expected));
  }
  return text;
}

}  // namespace hybridtest
