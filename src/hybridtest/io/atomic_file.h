#pragma once
// Small files replaced atomically, and the file-system steps that make a result durable. Used
// by the Journal for its sidecar and to publish a new run (docs/results-format.md).
//
// WriteFileAtomically(path, text): text goes to "<path>.tmp" (created if missing, never
// truncated first), is cut to its length, fsync'ed, and renamed over `path`; then the
// directory is synced. A reader sees the old file or the new one, never a mix.
//
// A full disk: writing a new file needs free blocks, so a sidecar could not record that its
// run stopped for lack of space. ReserveSpace(path, bytes) allocates the blocks of
// "<path>.tmp" in advance (posix_fallocate); the next WriteFileAtomically(path, ...) writes
// into them and needs no new block as long as the text fits.
#include <cstdint>
#include <string>

namespace hybridtest::io {

// "<path>.tmp": the temporary file WriteFileAtomically and ReserveSpace use.
std::string AtomicTempPath(const std::string& path);

// See above. Throws IoError naming the file and the system's reason; the temporary file is
// removed on failure and `path` is left as it was.
void WriteFileAtomically(const std::string& path, const std::string& text);

// Allocates `bytes` [B] for the next WriteFileAtomically(path, ...). Best effort: returns
// false (and leaves no file) if the space cannot be allocated.
bool ReserveSpace(const std::string& path, std::int64_t bytes);

// Makes a rename, a creation or a removal in `directory` durable. Best effort: some file
// systems cannot sync a directory.
void SyncDirectory(const std::string& directory);

// The directory holding `path` ("." for a bare file name).
std::string ParentDirectory(const std::string& path);

// strerror(errno), read at once.
std::string OsError();

}  // namespace hybridtest::io
