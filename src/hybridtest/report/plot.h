#pragma once
// The figures of one run, like the paper's Fig. 6 (hybrid test) and Fig. 7 (numerical run).
//
// For the rotor (plot_layout.h says how it is recognised):
//   displacements        blade-tip displacements q1..qN [m] against time; the coordinates of
//                        physical substructures in red and thicker (Fig. 6a)
//   hub-speed            hub angular speed u<N+1> [rad/s] against time (Fig. 6b)
// For any other model:
//   coordinates[-k]      all coordinates, one figure per unit, physical ones highlighted
//   speeds[-k]           all speeds, one figure per unit
// For each physical substructure <slot> whose channels are in the CSV:
//   <slot>-command-position   actuator command and measured position against time
//   <slot>-force-displacement measured restoring force against measured position (hysteresis)
// Lines over kMaxPlotPoints samples are decimated for drawing only (plot_decimate.h).
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"
#include "hybridtest/report/plot_figure.h"

namespace hybridtest::report {

// The figures described above, ready to render. Throws IoError if the run has no "t" channel
// or no rows.
std::vector<PlotFigure> MakeRunFigures(const io::RunData& run);

// Renders MakeRunFigures(run) into out_dir as PNG and SVG; returns the files written.
std::vector<std::string> WritePlots(const io::RunData& run, const std::string& out_dir,
                                    const GnuplotOptions& options = {});

// Default figure directory: <directory of the CSV>/<run name>-figures.
std::string DefaultPlotDir(const std::string& csv_path);

// The time column of a run, checked: throws IoError if "t" is missing or there are no rows.
// Unit: [s]
Eigen::VectorXd RunTime(const io::RunData& run);

}  // namespace hybridtest::report
