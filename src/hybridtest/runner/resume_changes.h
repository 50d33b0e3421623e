#pragma once
// A deliberate change of a safety limit, a timeout or a resume tolerance, made when a run is
// continued (`hybridtest resume RUN.csv --set KEY=VALUE`, Python's hybridtest.resume(set=...)). A resume otherwise uses the
// config the run started with (its sidecar's copy), so an edited file changes nothing; a
// change made here is checked like the config (a limit set must stay consistent) and
// recorded in the sidecar's resume record ("changes": [{key, from, to}]).
//
// Keys (SI):
//   substructures.SLOT.safety.stroke_min | stroke_max | max_increment [m]
//   substructures.SLOT.safety.force_soft | force_hard [N], timeout [s]
//   resume.force_tolerance [N], resume.position_tolerance [m]
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "hybridtest/io/run_spec.h"

namespace hybridtest::runner {

// Applies every `KEY=VALUE` to `spec`, in order. Throws ConfigError naming the setting and
// what is accepted (an unknown key, a slot that is not physical, a value that is not a finite
// number, limits that become inconsistent). Returns the changes made.
nlohmann::json ApplyResumeChanges(io::RunSpec& spec, const std::vector<std::string>& settings);

}  // namespace hybridtest::runner
