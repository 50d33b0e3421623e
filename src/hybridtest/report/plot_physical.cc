// The figures of each physical substructure (plot.h) and the helpers plot.cc shares.
#include <fmt/core.h>

#include "hybridtest/report/limit_use.h"
#include "hybridtest/report/plot_figure.h"
#include "hybridtest/report/plot_series.h"

namespace hybridtest::report {

Eigen::VectorXd DisplayValues(const io::RunData& run, const std::string& name,
                              const PlotUnits& units) {
  return ChannelValues(run, name) * units.Factor(ChannelUnit(run, name));
}

std::string DisplaySuffix(const io::RunData& run, const std::string& name,
                          const PlotUnits& units) {
  const std::string unit = ChannelUnit(run, name);
  return unit.empty() ? " [unit not recorded]" : " [" + units.Label(unit) + "]";
}

std::string PhysicalSlotColor(std::size_t index) {
  const auto& palette = PhysicalPalette();
  return palette[index % palette.size()];
}

int PhysicalIndexOfCoordinate(const RunLayout& layout, const std::string& coordinate) {
  for (std::size_t i = 0; i < layout.physical.size(); ++i) {
    if (!coordinate.empty() && layout.physical[i].coordinate == coordinate) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

int PhysicalIndexOfSlot(const RunLayout& layout, const std::string& slot) {
  for (std::size_t i = 0; i < layout.physical.size(); ++i) {
    if (layout.physical[i].slot == slot) return static_cast<int>(i);
  }
  return -1;
}

void AddPhysicalFigures(const io::RunData& run, const RunLayout& layout, const Eigen::VectorXd& t,
                        const PlotUnits& units, std::vector<PlotFigure>& figures) {
  for (std::size_t k = 0; k < layout.physical.size(); ++k) {
    const PhysicalChannels& p = layout.physical[k];
    const std::string color = PhysicalSlotColor(k);
    const std::string who = "Physical substructure " + p.slot;
    const std::string run_name = " (run " + layout.name + ")";
    // Tracking: command against measured position, and their difference.
    if (!p.position.empty() && !p.command.empty()) {
      const Eigen::VectorXd position = DisplayValues(run, p.position, units);
      const Eigen::VectorXd command = DisplayValues(run, p.command, units);
      PlotPanel positions;
      positions.title = "command and measured position";
      positions.x_label = kTimeLabel;
      positions.y_label = "actuator position" + DisplaySuffix(run, p.position, units);
      positions.series.push_back({"measured", t, position, color, 2.5, false});
      positions.series.push_back({"command", t, command, "#202020", 1.2, true});
      PlotPanel error;
      error.title = "tracking error (measured \u2212 command)";
      error.x_label = kTimeLabel;
      error.y_label = "measured \u2212 command" + DisplaySuffix(run, p.position, units);
      error.series.push_back({p.slot + " tracking error", t, position - command, color, 1.5,
                              false});
      figures.push_back({p.slot + "-command-position",
                         who + ": command, measured position and tracking error" + run_name,
                         {positions, error}});
    }
    // The measured force over time.
    if (!p.force.empty()) {
      PlotPanel panel;
      panel.x_label = kTimeLabel;
      panel.y_label = "measured force " + p.force + DisplaySuffix(run, p.force, units);
      panel.series.push_back({p.force + " (physical)", t, DisplayValues(run, p.force, units),
                              color, 1.5, false});
      figures.push_back({p.slot + "-force-time", who + ": measured force" + run_name, {panel}});
    }
    // Hysteresis: force against position.
    if (!p.position.empty() && !p.force.empty()) {
      PlotPanel panel;
      panel.x_label = "measured position " + p.position + DisplaySuffix(run, p.position, units);
      panel.x_is_time = false;
      panel.y_label =
          "measured restoring force " + p.force + DisplaySuffix(run, p.force, units);
      panel.series.push_back({p.slot + " (physical)", DisplayValues(run, p.position, units),
                              DisplayValues(run, p.force, units), color, 1.5, false});
      figures.push_back(
          {p.slot + "-force-displacement", who + ": force against displacement" + run_name,
           {panel}});
    }
    // Lab time against simulated time: the pace of the test.
    if (!p.lab_time.empty()) {
      PlotPanel panel;
      panel.x_label = kTimeLabel;
      panel.y_label = "lab time " + p.lab_time + DisplaySuffix(run, p.lab_time, units);
      panel.series.push_back({p.lab_time, t, DisplayValues(run, p.lab_time, units), color, 1.5,
                              false});
      figures.push_back({p.slot + "-lab-time", who + ": lab time against simulated time" +
                                                   run_name,
                         {panel}});
    }
    // The use of each safety limit.
    const std::vector<LimitUse> uses = CalcLimitUse(run, p);
    if (!uses.empty()) {
      PlotPanel panel;
      panel.x_label = kTimeLabel;
      panel.y_label = "use of the limit [%]";
      const auto& palette = NonPhysicalPalette();
      for (std::size_t i = 0; i < uses.size(); ++i) {
        const LimitUse& use = uses[i];
        panel.series.push_back({fmt::format("{} (peak {:.3g} %)", use.limit, 100 * use.peak),
                                use.t, 100 * use.use, palette[i % palette.size()], 1.5,
                                use.limit == "force_soft"});
      }
      figures.push_back({p.slot + "-limits", who + ": use of each safety limit" + run_name,
                         {panel}});
    }
  }
}

}  // namespace hybridtest::report
