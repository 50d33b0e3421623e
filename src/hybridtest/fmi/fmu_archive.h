#pragma once
// An FMU is a zip archive (FMI 2.0, section 2.4; FMI 3.0, section 2.5): modelDescription.xml
// at its root, binaries/<platform>/<modelIdentifier>.so, optional resources/. These read and
// write such archives with Debian's libzip. Errors name the archive and what was wrong.
#include <string>
#include <utility>
#include <vector>

namespace hybridtest::fmi {

// The names of the archive's members, in archive order. Throws ConfigError if `fmu` is not a
// readable zip archive.
std::vector<std::string> ListMembers(const std::string& fmu);

// The bytes of member `name` ("modelDescription.xml"). Throws ConfigError if the archive
// has no such member or cannot be read.
std::string ReadMember(const std::string& fmu, const std::string& name);

// Unpacks every member into `dir` (created if missing). A member whose name is absolute or
// climbs out with ".." is refused (ConfigError): an archive must not write outside `dir`.
void ExtractArchive(const std::string& fmu, const std::string& dir);

// Writes a zip archive at `path` with these members (name, bytes), replacing any file there.
// Throws IoError.
void WriteArchive(const std::string& path,
                  const std::vector<std::pair<std::string, std::string>>& members);

}  // namespace hybridtest::fmi
