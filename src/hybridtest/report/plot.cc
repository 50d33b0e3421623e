#include "hybridtest/report/plot.h"

#include <filesystem>
#include <map>

#include "hybridtest/common/error.h"
#include "hybridtest/report/plot_layout.h"

namespace hybridtest::report {
namespace {

const char* kTimeLabel = "time t [s]";

// One panel with a line per channel against time; physical coordinates are drawn last, in red
// and thicker, so that they stay visible on top of the others.
PlotPanel MakeHistoryPanel(const io::RunData& run, const RunLayout& layout,
                           const Eigen::VectorXd& time, const std::vector<std::string>& channels,
                           const std::string& y_label) {
  PlotPanel panel;
  panel.x_label = kTimeLabel;
  panel.y_label = y_label;
  std::vector<PlotSeries> physical;
  std::size_t colour = 0;
  for (const std::string& name : channels) {
    PlotSeries series{name, time, ChannelValues(run, name)};
    if (layout.physical_coordinates.count(name) > 0) {
      std::string slot;
      for (const PhysicalChannels& p : layout.physical) {
        if (p.coordinate == name) slot = p.slot;
      }
      series.label = name + " (physical" + (slot.empty() ? "" : ", " + slot) + ")";
      series.color = kPhysicalColor;
      series.line_width = kPhysicalLineWidth;
      physical.push_back(std::move(series));
      continue;
    }
    const auto& palette = NonPhysicalPalette();
    series.color = palette[colour++ % palette.size()];
    series.line_width = kNormalLineWidth;
    panel.series.push_back(std::move(series));
  }
  for (PlotSeries& s : physical) panel.series.push_back(std::move(s));
  return panel;
}

// "q1..q3" or "q1" or "q1, q3".
std::string ListNames(const std::vector<std::string>& names) {
  if (names.size() > 2) return names.front() + ".." + names.back();
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Channels grouped by recorded unit, in order of first appearance.
std::vector<std::pair<std::string, std::vector<std::string>>> GroupByUnit(
    const io::RunData& run, const std::vector<std::string>& names) {
  std::vector<std::pair<std::string, std::vector<std::string>>> groups;
  for (const std::string& name : names) {
    const std::string unit = ChannelUnit(run, name);
    auto it = std::find_if(groups.begin(), groups.end(),
                           [&](const auto& g) { return g.first == unit; });
    if (it == groups.end()) {
      groups.push_back({unit, {name}});
    } else {
      it->second.push_back(name);
    }
  }
  return groups;
}

// One figure per unit group: <stem> for a single group, <stem>-1, <stem>-2, ... otherwise.
void AddGroupedFigures(const io::RunData& run, const RunLayout& layout, const Eigen::VectorXd& t,
                       const std::vector<std::string>& names, const std::string& stem,
                       const std::string& what, std::vector<PlotFigure>& figures) {
  const auto groups = GroupByUnit(run, names);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto& [unit, channels] = groups[g];
    const std::string suffix = UnitSuffix(run, channels.front());
    PlotFigure figure;
    figure.stem = groups.size() == 1 ? stem : stem + "-" + std::to_string(g + 1);
    figure.title = what + " " + ListNames(channels) + " (run " + layout.name + ")";
    figure.panels.push_back(MakeHistoryPanel(run, layout, t, channels, what + suffix));
    figures.push_back(std::move(figure));
  }
}

// Command against measured position over time, and force against position.
void AddPhysicalFigures(const io::RunData& run, const RunLayout& layout, const Eigen::VectorXd& t,
                        std::vector<PlotFigure>& figures) {
  for (const PhysicalChannels& p : layout.physical) {
    const std::string who = "Physical substructure " + p.slot;
    if (!p.position.empty() && !p.command.empty()) {
      PlotPanel panel;
      panel.x_label = kTimeLabel;
      panel.y_label = "actuator position" + UnitSuffix(run, p.position);
      panel.series.push_back({"measured", t,
                              ChannelValues(run, p.position), kPhysicalColor, 2.5, false});
      panel.series.push_back({"command", t, ChannelValues(run, p.command),
                              "#202020", 1.2, true});
      figures.push_back({p.slot + "-command-position",
                         who + ": command and measured position (run " + layout.name +
                             ")",
                         {panel}});
    }
    if (!p.position.empty() && !p.force.empty()) {
      PlotPanel panel;
      panel.x_label = "measured position " + p.position + UnitSuffix(run, p.position);
      panel.x_is_time = false;
      panel.y_label = "measured restoring force " + p.force + UnitSuffix(run, p.force);
      panel.series.push_back({p.slot + " (physical)", ChannelValues(run, p.position),
                              ChannelValues(run, p.force), kPhysicalColor, 1.5, false});
      figures.push_back({p.slot + "-force-displacement",
                         who + ": force against displacement (run " + layout.name +
                             ")",
                         {panel}});
    }
  }
}

}  // namespace

Eigen::VectorXd RunTime(const io::RunData& run) {
  if (run.values.rows() == 0) {
    throw IoError(run.csv_path + ": the run has no rows; expected at least one committed step");
  }
  return ChannelValues(run, "t");
}

std::vector<PlotFigure> MakeRunFigures(const io::RunData& run) {
  const Eigen::VectorXd t = RunTime(run);
  const RunLayout layout = DescribeRun(run);
  std::vector<PlotFigure> figures;
  if (layout.is_rotor) {
    // Fig. 6a / 7a: the blades.
    if (!layout.blades.empty()) {
      PlotFigure figure;
      figure.stem = "displacements";
      figure.title = "Blade-tip displacements " + ListNames(layout.blades) + " (run " +
                     layout.name + ")";
      figure.panels.push_back(MakeHistoryPanel(run, layout, t, layout.blades,
                                               "blade-tip displacement" +
                                                   UnitSuffix(run, layout.blades.front())));
      figures.push_back(std::move(figure));
    }
    // Fig. 6b / 7b: the hub speed.
    if (!layout.hub_speed.empty()) {
      PlotFigure figure;
      figure.stem = "hub-speed";
      figure.title = "Hub angular speed " + layout.hub_speed + " (run " + layout.name + ")";
      figure.panels.push_back(MakeHistoryPanel(
          run, layout, t, {layout.hub_speed},
          "hub angular speed " + layout.hub_speed + UnitSuffix(run, layout.hub_speed)));
      figures.push_back(std::move(figure));
    }
  } else {
    AddGroupedFigures(run, layout, t, layout.coordinates, "coordinates", "Generalized coordinates",
                      figures);
    AddGroupedFigures(run, layout, t, layout.speeds, "speeds", "Generalized speeds", figures);
  }
  AddPhysicalFigures(run, layout, t, figures);
  // Where the run was resumed (hybridtest resume), on every time axis.
  const nlohmann::json& meta = run.metadata;
  if (meta.is_object() && meta.contains("resumes") && meta["resumes"].is_array()) {
    for (const auto& r : meta["resumes"]) {
      if (!r.is_object() || !r.contains("t") || !r["t"].is_number()) continue;
      for (auto& figure : figures) {
        for (auto& panel : figure.panels) {
          if (panel.x_is_time) panel.marks.emplace_back(r["t"].get<double>(), "resumed");
        }
      }
    }
  }
  return figures;
}

std::vector<std::string> WritePlots(const io::RunData& run, const std::string& out_dir,
                                    const GnuplotOptions& options) {
  return RenderFigures(MakeRunFigures(run), out_dir, options);
}

std::string DefaultPlotDir(const std::string& csv_path) {
  const std::filesystem::path path(csv_path);
  return (path.parent_path() / (path.stem().string() + "-figures")).string();
}

}  // namespace hybridtest::report
