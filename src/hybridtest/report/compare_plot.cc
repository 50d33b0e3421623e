#include "hybridtest/report/compare_plot.h"

#include <algorithm>

#include "hybridtest/report/compare.h"
#include "hybridtest/report/plot.h"
#include "hybridtest/report/plot_layout.h"

namespace hybridtest::report {
namespace {

constexpr const char* kColorA = "#1f77b4";
constexpr const char* kColorB = "#303030";

// The channels of names that run b also has.
std::vector<std::string> Common(const std::vector<std::string>& names, const io::RunData& b) {
  std::vector<std::string> common;
  for (const std::string& n : names) {
    if (FindChannel(b, n) >= 0) common.push_back(n);
  }
  return common;
}

PlotSeries RunLine(const io::RunData& run, const RunLayout& layout, const std::string& channel,
                   const std::string& name, const char* color, bool dashed) {
  PlotSeries line{name, RunTime(run), ChannelValues(run, channel), color, kNormalLineWidth,
                  dashed};
  if (layout.physical_coordinates.count(channel) > 0) {
    line.label = name + " (physical)";
    line.color = kPhysicalColor;
    line.line_width = 2.5;
  }
  return line;
}

// One panel per channel with A and B overlaid.
PlotFigure OverlayFigure(const io::RunData& a, const io::RunData& b, const std::string& stem,
                         const std::string& title, const std::string& what,
                         const std::vector<std::string>& channels) {
  const RunLayout la = DescribeRun(a), lb = DescribeRun(b);
  const auto [name_a, name_b] = DistinctRunNames(a, b);
  PlotFigure figure{stem, title, {}};
  for (const std::string& channel : channels) {
    PlotPanel panel;
    panel.title = channel;
    panel.x_label = "time t [s]";
    panel.y_label = what + " " + channel + UnitSuffix(a, channel);
    panel.series.push_back(RunLine(a, la, channel, name_a, kColorA, false));
    panel.series.push_back(RunLine(b, lb, channel, name_b, kColorB, true));
    figure.panels.push_back(std::move(panel));
  }
  return figure;
}

}  // namespace

std::vector<PlotFigure> MakeComparisonFigures(const io::RunData& a, const io::RunData& b) {
  const RunLayout la = DescribeRun(a);
  const auto [name_a, name_b] = DistinctRunNames(a, b);
  const std::string versus = " (" + name_a + " against " + name_b + ")";
  std::vector<PlotFigure> figures;
  if (la.is_rotor) {
    const auto blades = Common(la.blades, b);
    if (!blades.empty()) {
      figures.push_back(OverlayFigure(a, b, "compare-displacements",
                                      "Blade-tip displacements" + versus, "displacement", blades));
    }
    if (!la.hub_speed.empty() && FindChannel(b, la.hub_speed) >= 0) {
      figures.push_back(OverlayFigure(a, b, "compare-hub-speed", "Hub angular speed" + versus,
                                      "hub speed", {la.hub_speed}));
    }
  } else {
    const auto coordinates = Common(la.coordinates, b);
    if (!coordinates.empty()) {
      figures.push_back(OverlayFigure(a, b, "compare-coordinates",
                                      "Generalized coordinates" + versus, "coordinate",
                                      coordinates));
    }
    const auto speeds = Common(la.speeds, b);
    if (!speeds.empty()) {
      figures.push_back(OverlayFigure(a, b, "compare-speeds", "Generalized speeds" + versus,
                                      "speed", speeds));
    }
  }
  return figures;
}

std::vector<std::string> WriteComparisonPlots(const io::RunData& a, const io::RunData& b,
                                              const std::string& out_dir,
                                              const GnuplotOptions& options) {
  return RenderFigures(MakeComparisonFigures(a, b), out_dir, options);
}

}  // namespace hybridtest::report
