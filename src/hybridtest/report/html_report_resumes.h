#pragma once
// The report's "Resumes" section: one table row per entry of the sidecar's `resumes` array
// (docs/results-format.md, "Run state"): when, from which step and model time [s], what had
// stopped the run, and each physical slot's force check (committed and measured force [N],
// tolerance [N]). Empty string for a run that was never resumed.
#include <nlohmann/json.hpp>

#include <string>

namespace hybridtest::report {

std::string ResumesSection(const nlohmann::json& sidecar);

// The report's "Operator actions" section: one row per entry of the sidecar's
// `operator_actions` (docs/monitor.md: Hold, Continue, Stop from the monitor), with the action,
// step, model time [s], when it was asked and applied (UTC) and from where. Empty string for a
// run nobody intervened in.
std::string OperatorActionsSection(const nlohmann::json& sidecar);

}  // namespace hybridtest::report
