#pragma once
// The compiled-model cache kept private (issue 45 item 2, docs/equations.md, "Cache"): a
// library is loaded only from a directory that only its user can write, only if the library,
// its C source and its digest record are that user's and writable by no one else, and only if
// both digests equal the ones recorded when it was built. The check runs on an open file
// descriptor before dlopen (the library's constructors run at dlopen, before any numeric
// check), and the library is loaded from that descriptor, so the bytes checked are the bytes
// loaded.
//
// Per library NAME-HASH.so the cache holds NAME-HASH.c (its source), NAME-HASH.sha256 (the
// record: "library <hex>\nsource <hex>\n", SHA-256) and NAME-HASH.lock (held exclusively while
// it is built, shared while it is checked).
#include <filesystem>
#include <string>

namespace hybridtest::symbolic {

// Creates `dir` if missing (its last component mode 0700), then throws Error unless it is a
// directory owned by this process's user and not writable by group or others, naming the
// directory, what is wrong and the fix.
void PreparePrivateDir(const std::filesystem::path& dir);

// NAME-HASH.c and NAME-HASH.sha256 beside NAME-HASH.so.
std::filesystem::path SourceOf(const std::filesystem::path& library);
std::filesystem::path RecordOf(const std::filesystem::path& library);

// Writes the record of `library` built from `source` to `record` (mode 0600).
void WriteDigestRecord(const std::filesystem::path& library, const std::filesystem::path& source,
                       const std::filesystem::path& record);

// An advisory lock (flock) on NAME-HASH.lock beside `library`, released by the destructor.
class CacheLock {
 public:
  CacheLock(const std::filesystem::path& library, bool exclusive);
  ~CacheLock();
  CacheLock(const CacheLock&) = delete;
  CacheLock& operator=(const CacheLock&) = delete;

 private:
  int fd_ = -1;
};

// Opens `library` and checks it (its directory, owner, mode, type, and both digests against
// its record). Returns the open descriptor (the caller closes it after dlopen of
// "/proc/self/fd/N"). Throws ModelError naming the file, what failed and the fix.
int OpenCheckedLibrary(const std::filesystem::path& library);

}  // namespace hybridtest::symbolic
