#pragma once
// An FMU is a zip archive (FMI 2.0, section 2.4; FMI 3.0, section 2.5): modelDescription.xml
// at its root, binaries/<platform>/<modelIdentifier>.so, optional resources/. These read and
// write such archives with Debian's libzip. Errors name the archive and what was wrong.
#include <string>
#include <utility>
#include <vector>

namespace hybridtest::fmi {

// Every read is bounded, checked while the bytes stream (a declared size is never trusted and
// never allocated up front): an archive that breaks a limit below is refused with a
// ConfigError naming the FMU, the member, the limit and its value (docs/fmi.md, "Limits").
// An FMU of a model is a few megabytes; these leave a wide margin.
inline constexpr long long kMaxFmuMembers = 10000;          // members of one archive
inline constexpr long long kMaxFmuMemberBytes = 1LL << 30;  // one member unpacked. Unit: [bytes]
inline constexpr long long kMaxFmuTotalBytes = 2LL << 30;   // all members. Unit: [bytes]
inline constexpr long long kMaxFmuRatio = 200;              // unpacked / compressed, one member
inline constexpr long long kFmuRatioFloorBytes = 1LL << 20;  // ratio checked above. Unit: [bytes]

// The names of the archive's members, in archive order. Throws ConfigError if `fmu` is not a
// readable zip archive.
std::vector<std::string> ListMembers(const std::string& fmu);

// The bytes of member `name` ("modelDescription.xml"). Throws ConfigError if the archive
// has no such member, cannot be read or breaks a limit above.
std::string ReadMember(const std::string& fmu, const std::string& name);

// Unpacks every member into `dir` (created if missing). A member whose name is absolute or
// climbs out with ".." is refused (ConfigError): an archive must not write outside `dir`;
// so is one that breaks a limit above (what was written so far stays in `dir`).
void ExtractArchive(const std::string& fmu, const std::string& dir);

// Writes a zip archive at `path` with these members (name, bytes), replacing any file there.
// Throws IoError.
void WriteArchive(const std::string& path,
                  const std::vector<std::pair<std::string, std::string>>& members);

// A fresh private folder to unpack one FMU in (under the temporary directory). Throws IoError.
std::string MakeUnpackDir();

// Bytes as lowercase hex digits (an FMU state in a run state's JSON), and back (throws Error
// for an odd count or a non-hex digit).
std::string ToHex(const std::string& bytes);
std::string FromHex(const std::string& hex);

}  // namespace hybridtest::fmi
