// The private compiled-model cache. See model_cache.h.
#include "hybridtest/symbolic/model_cache.h"

#include <fcntl.h>
#include <fmt/core.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "hybridtest/common/digest.h"
#include "hybridtest/common/error.h"

namespace hybridtest::symbolic {

namespace fs = std::filesystem;

namespace {

std::string OsError() { return std::strerror(errno); }

// Empty if `st` is owned by this user and writable by no one else; otherwise what is wrong.
std::string Ownership(const struct stat& st) {
  if (st.st_uid != geteuid()) {
    return fmt::format("it is owned by user id {}, not by this user ({})", st.st_uid, geteuid());
  }
  if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    return fmt::format("it is writable by {} (mode {:o})",
                       (st.st_mode & S_IWOTH) != 0 ? "others" : "its group", st.st_mode & 07777);
  }
  return {};
}

// Empty if the stat call that returned `rc` found a directory (or a regular file) of this
// user writable by no one else; otherwise what is wrong.
std::string Problem(int rc, const struct stat& st, bool directory) {
  if (rc != 0) return OsError();
  if (directory ? !S_ISDIR(st.st_mode) : !S_ISREG(st.st_mode)) {
    return directory ? "it is not a directory" : "it is not a regular file";
  }
  return Ownership(st);
}

// The whole content of the open file `fd` (from its start).
std::string ReadFd(int fd, const fs::path& path) {
  std::string bytes;
  char buffer[1 << 16];
  for (off_t at = 0;;) {
    const ssize_t n = pread(fd, buffer, sizeof buffer, at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw ModelError(fmt::format("{}: cannot read it to check its digest: {}", path.string(),
                                   OsError()));
    }
    if (n == 0) return bytes;
    bytes.append(buffer, static_cast<std::size_t>(n));
    at += n;
  }
}

// Opens `path` (no symbolic link), checks it is a regular file of this user writable by no one
// else; returns the descriptor. `what` names the file in messages.
int OpenPrivateFile(const fs::path& path, const char* what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    throw ModelError(fmt::format("the compiled model's {} {} cannot be opened: {}; delete the "
                                 "library and compile again", what, path.string(), OsError()));
  }
  struct stat st {};
  const std::string problem = Problem(::fstat(fd, &st), st, false);
  if (!problem.empty()) {
    ::close(fd);
    throw ModelError(fmt::format("refusing to load the compiled model: its {} {}: {}; the cache "
                                 "must be private to you: delete the file (and check who wrote "
                                 "it), then compile again", what, path.string(), problem));
  }
  return fd;
}

std::string DigestOfPrivateFile(const fs::path& path, const char* what) {
  const int fd = OpenPrivateFile(path, what);
  try {
    std::string digest = Sha256Hex(ReadFd(fd, path));
    ::close(fd);
    return digest;
  } catch (...) {
    ::close(fd);
    throw;
  }
}

}  // namespace

void PreparePrivateDir(const fs::path& dir) {
  std::error_code ec;
  const bool existed = fs::exists(dir, ec);
  if (!existed) {
    fs::create_directories(dir.parent_path(), ec);
    if (!ec && ::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) {
      ec = std::error_code(errno, std::generic_category());
    }
    if (ec) {
      throw Error(fmt::format("cannot create the cache of compiled models {}: {}; set "
                              "HYBRIDTEST_CACHE_DIR to a writable directory", dir.string(),
                              ec.message()));
    }
  }
  struct stat st {};
  const std::string problem = Problem(::stat(dir.c_str(), &st), st, true);
  if (!problem.empty()) {
    throw Error(fmt::format(
        "refusing the cache of compiled models {}: {}; a library there is loaded into this "
        "process, so the cache must be yours and writable only by you: `chmod go-w {}` if it is "
        "yours, or set HYBRIDTEST_CACHE_DIR to a directory of your own",
        dir.string(), problem, dir.string()));
  }
}

fs::path SourceOf(const fs::path& library) { return fs::path(library).replace_extension(".c"); }
fs::path RecordOf(const fs::path& library) {
  return fs::path(library).replace_extension(".sha256");
}

void WriteDigestRecord(const fs::path& library, const fs::path& source, const fs::path& record) {
  const std::string text = fmt::format("library {}\nsource {}\n", Sha256OfFile(library.string()),
                                       Sha256OfFile(source.string()));
  const int fd = ::open(record.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const bool ok = fd >= 0 && ::write(fd, text.data(), text.size()) ==
                                 static_cast<ssize_t>(text.size());
  if (fd >= 0) ::close(fd);
  if (!ok) throw Error(fmt::format("cannot write {}: {}", record.string(), OsError()));
}

CacheLock::CacheLock(const fs::path& library, bool exclusive) {
  const fs::path lock = fs::path(library).replace_extension(".lock");
  fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd_ < 0) throw Error(fmt::format("cannot open {}: {}", lock.string(), OsError()));
  while (::flock(fd_, exclusive ? LOCK_EX : LOCK_SH) != 0) {
    if (errno != EINTR) {
      ::close(fd_);
      throw Error(fmt::format("cannot lock {}: {}", lock.string(), OsError()));
    }
  }
}

CacheLock::~CacheLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

int OpenCheckedLibrary(const fs::path& library) {
  try {
    PreparePrivateDir(library.parent_path().empty() ? fs::path(".") : library.parent_path());
  } catch (const Error& e) {
    throw ModelError(e.what());
  }
  // The record: "library <hex>\nsource <hex>\n".
  const fs::path record = RecordOf(library);
  std::string want_library, want_source;
  {
    const int fd = OpenPrivateFile(record, "digest record");
    std::string text;
    try {
      text = ReadFd(fd, record);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
    char lib[65] = {}, src[65] = {};
    if (text.size() > 256 ||
        std::sscanf(text.c_str(), "library %64[0-9a-f]\nsource %64[0-9a-f]", lib, src) != 2) {
      throw ModelError(fmt::format("refusing to load the compiled model {}: its digest record {} "
                                   "is not one hybridtest wrote; delete the library and compile "
                                   "again", library.string(), record.string()));
    }
    want_library = lib;
    want_source = src;
  }
  const std::string source_digest = DigestOfPrivateFile(SourceOf(library), "source");
  if (source_digest != want_source) {
    throw ModelError(fmt::format(
        "refusing to load the compiled model {}: digest mismatch: its source {} has SHA-256 {}, "
        "the record says {}; delete the library and compile again", library.string(),
        SourceOf(library).string(), source_digest, want_source));
  }
  const int fd = OpenPrivateFile(library, "library");
  std::string digest;
  try {
    digest = Sha256Hex(ReadFd(fd, library));
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (digest != want_library) {
    ::close(fd);
    throw ModelError(fmt::format(
        "refusing to load the compiled model {}: digest mismatch: the library has SHA-256 {}, "
        "the record written when it was built from {} says {}; it was replaced after it was "
        "built: delete it (and check who wrote it), then compile again", library.string(),
        digest, SourceOf(library).string(), want_library));
  }
  return fd;
}

}  // namespace hybridtest::symbolic
