#pragma once
// A run as a CSV for lab tools (spreadsheets, DIAdem, MATLAB's readtable): the channel names on
// the first line, their units on the second, then the rows, optionally in lab units
// (report/plot_units.h: lengths in mm, forces in kN, ...). The journal itself keeps a single
// header line, because resume, compare and every reader of a run parse it as written
// (docs/results-format.md); this is its export.
#include <string>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/plot_units.h"

namespace hybridtest::report {

// Writes `run` to `path` as above, with every value converted by `units` (Factor of the
// channel's unit) and printed in the shortest form that reads back exactly.
// Missing samples (NaN) are written as empty fields. Throws IoError if the file cannot be
// written, naming it.
void ExportCsvWithUnits(const io::RunData& run, const std::string& path, const PlotUnits& units);

}  // namespace hybridtest::report
