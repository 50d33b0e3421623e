#pragma once
// Where an exported FMU finds its resources, from what the importer passes: FMI 2 a file URI
// ("file:///tmp/x/resources", "file:/tmp/x/resources"), FMI 3 a folder path; and the check
// that the importer names this FMU (its guid / instantiationToken, kept in export.json).
#include <string>

namespace hybridtest::fmu_export {

// The resources folder as a path (percent-escapes decoded). Throws Error for another scheme.
std::string ResourceFolder(const std::string& location);
// Throws Error unless `token` is the one export.json records (the description's guid).
void CheckToken(const std::string& resources, const std::string& token);

}  // namespace hybridtest::fmu_export
