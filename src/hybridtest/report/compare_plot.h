#pragma once
// Overlay figures of two runs, A against B (the paper's Fig. 6 against Fig. 7), one panel per
// channel, each line labelled by its run name (DistinctRunNames in compare.h):
//   compare-displacements   rotor: blades q1..qN, one panel each
//   compare-hub-speed       rotor: hub speed u<N+1>
//   compare-coordinates     other models: every coordinate both runs have
//   compare-speeds          other models: every speed both runs have
// A is solid, B dashed; a channel that is physical in a run is drawn in red in that run's line.
// The rotor layout is taken from run A.
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"
#include "hybridtest/report/plot_figure.h"

namespace hybridtest::report {

std::vector<PlotFigure> MakeComparisonFigures(const io::RunData& a, const io::RunData& b);

// Renders MakeComparisonFigures into out_dir (PNG and SVG); returns the files written.
std::vector<std::string> WriteComparisonPlots(const io::RunData& a, const io::RunData& b,
                                              const std::string& out_dir,
                                              const GnuplotOptions& options = {});

}  // namespace hybridtest::report
