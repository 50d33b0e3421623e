// See atomic_file.h.
#include "hybridtest/io/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "hybridtest/common/error.h"

namespace hybridtest::io {

std::string OsError() { return std::strerror(errno); }

std::string AtomicTempPath(const std::string& path) { return path + ".tmp"; }

std::string ParentDirectory(const std::string& path) {
  const auto parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

void SyncDirectory(const std::string& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string temp = AtomicTempPath(path);
  // No O_TRUNC: a reserved temporary file keeps its blocks, and the text is written into them.
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw IoError(fmt::format("{}: cannot create the temporary file: {}; check that the "
                              "directory exists and is writable",
                              temp, OsError()));
  }
  auto fail = [&](const std::string& what) {
    const std::string error = OsError();
    ::close(fd);
    ::unlink(temp.c_str());
    throw IoError(fmt::format("{}: {}: {}; check free disk space", temp, what, error));
  };
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::pwrite(fd, text.data() + written, text.size() - written,
                               static_cast<off_t>(written));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write " + std::filesystem::path(path).filename().string());
    written += static_cast<std::size_t>(n);
  }
  if (::ftruncate(fd, static_cast<off_t>(text.size())) != 0) fail("cannot cut it to length");
  if (::fsync(fd) != 0) fail("cannot sync it to disk");
  if (::close(fd) != 0) {
    const std::string error = OsError();
    ::unlink(temp.c_str());
    throw IoError(fmt::format("{}: cannot close it: {}", temp, error));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string error = OsError();
    ::unlink(temp.c_str());
    throw IoError(fmt::format("{}: cannot rename {} over it: {}", path, temp, error));
  }
  SyncDirectory(ParentDirectory(path));
}

bool ReserveSpace(const std::string& path, std::int64_t bytes) {
  const std::string temp = AtomicTempPath(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool ok = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes)) == 0;
  ::close(fd);
  if (!ok) ::unlink(temp.c_str());
  return ok;
}

}  // namespace hybridtest::io
