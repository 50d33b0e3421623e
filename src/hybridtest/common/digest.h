#pragma once
// SHA-256 digests (OpenSSL's libcrypto) for the records that must not lie: the run state's
// checksum, the journal's last row, the inputs a run read (docs/safety.md, "Resuming a run")
// and the compiled models of the cache (docs/equations.md). Hex strings, lower case, 64
// characters.
#include <string>
#include <string_view>

namespace hybridtest {

std::string Sha256Hex(std::string_view bytes);

// The digest of the file at `path`, read whole. Throws IoError naming the file if it cannot
// be read or is not a regular file.
std::string Sha256OfFile(const std::string& path);

}  // namespace hybridtest
