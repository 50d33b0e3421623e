#pragma once
// The report's "Real-time criteria" section: for a real-time run (rths_criteria.h,
// IsRealTimeRun), J1–J3 from the run alone and, against a reference structure (--against),
// J4–J9 too. Empty string for a run that is not real time. A reference that does not fit (no
// floor's coordinate) gives a note instead of the criteria it cannot give.
#include <string>

#include "hybridtest/io/run_reader.h"

namespace hybridtest::report {

std::string RthsSection(const io::RunData& run, const io::RunData* reference);

}  // namespace hybridtest::report
