#pragma once
// Shared pieces of the run figures (plot.cc, plot_physical.cc): channel values and axis
// suffixes in display units, and the colour of each slot.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/plot_figure.h"
#include "hybridtest/report/plot_layout.h"
#include "hybridtest/report/plot_units.h"

namespace hybridtest::report {

inline constexpr const char* kTimeLabel = "time t [s]";

// A channel's values converted to display units. Throws IoError like ChannelValues.
Eigen::VectorXd DisplayValues(const io::RunData& run, const std::string& name,
                              const PlotUnits& units);

// " [unit]" in display units, or " [unit not recorded]".
std::string DisplaySuffix(const io::RunData& run, const std::string& name,
                          const PlotUnits& units);

// The colour of physical substructure number `index` in layout.physical: every physical slot
// its own warm colour (the first is the paper's red), all of them absent from
// NonPhysicalPalette().
std::string PhysicalSlotColor(std::size_t index);

// Index in layout.physical of the slot acting on a coordinate, or of a slot by name; -1 when
// it is not physical.
int PhysicalIndexOfCoordinate(const RunLayout& layout, const std::string& coordinate);
int PhysicalIndexOfSlot(const RunLayout& layout, const std::string& slot);

// Adds the figures of every physical substructure (plot.h lists them).
void AddPhysicalFigures(const io::RunData& run, const RunLayout& layout, const Eigen::VectorXd& t,
                        const PlotUnits& units, std::vector<PlotFigure>& figures);

}  // namespace hybridtest::report
