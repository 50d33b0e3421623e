#pragma once
// The report's "Resumes" section: one table row per entry of the sidecar's `resumes` array
// (docs/results-format.md, "Run state"): when, from which step and model time [s], what had
// stopped the run, and each physical slot's force check (committed and measured force [N],
// tolerance [N]). Empty string for a run that was never resumed.
#include <nlohmann/json.hpp>

#include <string>

namespace hybridtest::report {

std::string ResumesSection(const nlohmann::json& sidecar);

}  // namespace hybridtest::report
