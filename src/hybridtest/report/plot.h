#pragma once
// The figures of one run, like the paper's Fig. 6 (hybrid test) and Fig. 7 (numerical run).
//
// For the rotor (plot_layout.h says how it is recognised):
//   displacements        blade-tip displacements q1..qN against time; the coordinates of
//                        physical substructures thicker, in their slot's colour (Fig. 6a)
//   hub-speed            hub angular speed u<N+1> [rad/s] against time (Fig. 6b)
// For any other model (a model file's own channel names, from the sidecar):
//   coordinates[-<names>]  every coordinate, one figure per group: channels of one unit whose
//                          peaks lie within a factor 30 (so the edgewise rotations of a wind
//                          turbine's blades are not flattened by its azimuth)
//   speeds[-<names>]       every speed, grouped the same way
// For every model:
//   restoring-forces[-<names>]  every slot's restoring force, grouped the same way
// For each physical substructure <slot> whose channels are in the CSV, in its own colour:
//   <slot>-command-position   command and measured position against time, and below them the
//                             tracking error (measured − command)
//   <slot>-force-time         measured force against time
//   <slot>-force-displacement measured restoring force against measured position (hysteresis)
//   <slot>-lab-time           the bench's lab time against simulated time (the test's pace)
//   <slot>-limits             the use of each safety limit in % against time (limit_use.h)
// Values are drawn in display units (plot_units.h; SI by default). Lines over kMaxPlotPoints
// samples are decimated for drawing only (plot_decimate.h).
#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"
#include "hybridtest/report/plot_figure.h"
#include "hybridtest/report/plot_units.h"

namespace hybridtest::report {

// The figures described above, ready to render. Throws IoError if the run has no "t" channel
// or no rows.
std::vector<PlotFigure> MakeRunFigures(const io::RunData& run, const PlotUnits& units = {});

// Renders MakeRunFigures(run) into out_dir as PNG and SVG; returns the files written.
std::vector<std::string> WritePlots(const io::RunData& run, const std::string& out_dir,
                                    const GnuplotOptions& options = {},
                                    const PlotUnits& units = {});

// Default figure directory: <directory of the CSV>/<run name>-figures.
std::string DefaultPlotDir(const std::string& csv_path);

// The time column of a run, checked: throws IoError if "t" is missing or there are no rows.
// Unit: [s]
Eigen::VectorXd RunTime(const io::RunData& run);

}  // namespace hybridtest::report
