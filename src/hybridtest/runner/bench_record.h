#pragma once
// What each physical substructure's bench said about itself, for the sidecar's statistics
// (`statistics.benches`): recorded when the run ends, after Activate(), so that a remote or
// Modbus bench's own account (known only once connected) is part of the test record.
#include <nlohmann/json.hpp>

#include "hybridtest/runner/run_record.h"

namespace hybridtest::runner {

// One entry per physical substructure (subs[s] built from spec.substructures[s]), in order:
//   {"slots": [..], "description": Describe() now, "units": {"length", "force",
//    "metres_per_length_unit", "newtons_per_force_unit"} (the wire's units),
//    "announced": {"source", "p0_m", "limits": {"stroke_min_m", "stroke_max_m",
//    "max_increment_m", "force_soft_n", "force_hard_n"}} (what the bench announced; absent
//    keys: not announced)}.
// Never throws for a bench that cannot tell (Announce() and Describe() never throw).
nlohmann::json BenchRecords(const SubstructureList& subs, const io::RunSpec& spec);

}  // namespace hybridtest::runner
