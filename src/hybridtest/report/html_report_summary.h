#pragma once
// The parts of the HTML report that state the result (html_report.h shows the page's order):
//   SummarySection       status (and the stop, if any); simulated time, steps, physical
//                        evaluations, lab time, wall time and slowdown; resumes; with a
//                        comparison, its headline errors (every coordinate and restoring
//                        force: max |A−B|, RMS, the amplitudes of both runs); the peak use of
//                        each safety limit of each physical slot (limit_use.h), flagged from
//                        90 %.
//   InitialStiffnessSection  the K0 record of the sidecar's statistics.initial_stiffness as a
//                        table: slot, source, K0 with its unit, and for a measured K0 the
//                        ramp's amplitude and number of samples.
// Numbers are rounded to what they mean (FormatNumber, FormatDuration); values are shown in
// the display units the report was asked for.
#include <string>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/compare.h"
#include "hybridtest/report/plot_layout.h"
#include "hybridtest/report/plot_units.h"

namespace hybridtest::report {

// comparison may be null (no --against).
std::string SummarySection(const io::RunData& run, const RunLayout& layout,
                           const ComparisonTable* comparison, const PlotUnits& units);

// "" when the sidecar has no K0 record.
std::string InitialStiffnessSection(const io::RunData& run, const PlotUnits& units);

}  // namespace hybridtest::report
