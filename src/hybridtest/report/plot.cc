#include "hybridtest/report/plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "hybridtest/common/error.h"
#include "hybridtest/report/plot_layout.h"
#include "hybridtest/report/plot_series.h"

namespace hybridtest::report {
namespace {

// Channels whose peaks differ by more than this factor are drawn in separate figures, so that
// a small coordinate (an edgewise blade rotation) is not flattened by a large one of the same
// unit (the rotor azimuth).
constexpr double kScaleSplit = 30.0;

// One panel with a line per channel against time. Physical channels (a physical slot's
// coordinate or restoring force) are drawn last, thick and in their slot's colour, so they
// stay visible on top of the others.
PlotPanel MakeHistoryPanel(const io::RunData& run, const RunLayout& layout,
                           const Eigen::VectorXd& time, const std::vector<std::string>& channels,
                           const std::string& y_label, const PlotUnits& units) {
  PlotPanel panel;
  panel.x_label = kTimeLabel;
  panel.y_label = y_label;
  std::vector<PlotSeries> physical;
  std::size_t colour = 0;
  for (const std::string& name : channels) {
    PlotSeries series{name, time, DisplayValues(run, name, units)};
    int index = PhysicalIndexOfCoordinate(layout, name);
    if (index < 0) index = PhysicalIndexOfSlot(layout, name);
    if (index >= 0) {
      const std::string& slot = layout.physical[static_cast<std::size_t>(index)].slot;
      series.label = name + " (physical" + (slot == name ? "" : ", " + slot) + ")";
      series.color = PhysicalSlotColor(static_cast<std::size_t>(index));
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

// A file-name-safe version of ListNames: "beta1-beta3", "x_t".
std::string StemOf(const std::vector<std::string>& names) {
  std::string text = names.size() > 1 ? names.front() + "-" + names.back() : names.front();
  for (char& c : text) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  }
  return text;
}

// Channels grouped by recorded unit (in order of first appearance), each group split where
// the channels' peaks differ by more than kScaleSplit.
std::vector<std::vector<std::string>> GroupChannels(const io::RunData& run,
                                                    const std::vector<std::string>& names) {
  std::vector<std::pair<std::string, std::vector<std::string>>> by_unit;
  for (const std::string& name : names) {
    const std::string unit = ChannelUnit(run, name);
    auto it = std::find_if(by_unit.begin(), by_unit.end(),
                           [&](const auto& g) { return g.first == unit; });
    if (it == by_unit.end()) {
      by_unit.push_back({unit, {name}});
    } else {
      it->second.push_back(name);
    }
  }
  std::vector<std::vector<std::string>> groups;
  for (const auto& [unit, channels] : by_unit) {
    std::vector<std::pair<std::string, double>> peaks;
    for (const std::string& name : channels) {
      double peak = 0;
      for (double v : ChannelValues(run, name)) {
        if (std::isfinite(v)) peak = std::max(peak, std::abs(v));
      }
      peaks.push_back({name, peak});
    }
    // Each group is anchored at its largest peak; channels far below it start another.
    std::vector<bool> placed(peaks.size(), false);
    for (;;) {
      double top = -1;
      for (std::size_t i = 0; i < peaks.size(); ++i) {
        if (!placed[i]) top = std::max(top, peaks[i].second);
      }
      if (top < 0) break;
      std::vector<std::string> group;
      for (std::size_t i = 0; i < peaks.size(); ++i) {
        if (!placed[i] && peaks[i].second * kScaleSplit >= top) {
          group.push_back(peaks[i].first);
          placed[i] = true;
        }
      }
      groups.push_back(group);
    }
  }
  return groups;
}

// One figure per group: <stem> for a single group, <stem>-<channels> otherwise.
void AddGroupedFigures(const io::RunData& run, const RunLayout& layout, const Eigen::VectorXd& t,
                       const std::vector<std::string>& names, const std::string& stem,
                       const std::string& what, const PlotUnits& units,
                       std::vector<PlotFigure>& figures) {
  if (names.empty()) return;
  const auto groups = GroupChannels(run, names);
  for (const std::vector<std::string>& channels : groups) {
    PlotFigure figure;
    figure.stem = groups.size() == 1 ? stem : stem + "-" + StemOf(channels);
    std::string title = what + " " + ListNames(channels);
    if (channels.size() == 1) {
      const std::string description = run.Description(channels.front());
      if (!description.empty()) title += ", " + description;
    }
    figure.title = title + " (run " + layout.name + ")";
    figure.panels.push_back(MakeHistoryPanel(
        run, layout, t, channels, what + DisplaySuffix(run, channels.front(), units), units));
    figures.push_back(std::move(figure));
  }
}

}  // namespace

Eigen::VectorXd RunTime(const io::RunData& run) {
  if (run.values.rows() == 0) {
    throw IoError(run.csv_path + ": the run has no rows; expected at least one committed step");
  }
  return ChannelValues(run, "t");
}

std::vector<PlotFigure> MakeRunFigures(const io::RunData& run, const PlotUnits& units) {
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
      figure.panels.push_back(MakeHistoryPanel(
          run, layout, t, layout.blades,
          "blade-tip displacement" + DisplaySuffix(run, layout.blades.front(), units), units));
      figures.push_back(std::move(figure));
    }
    // Fig. 6b / 7b: the hub speed.
    if (!layout.hub_speed.empty()) {
      PlotFigure figure;
      figure.stem = "hub-speed";
      figure.title = "Hub angular speed " + layout.hub_speed + " (run " + layout.name + ")";
      figure.panels.push_back(MakeHistoryPanel(
          run, layout, t, {layout.hub_speed},
          "hub angular speed " + layout.hub_speed + DisplaySuffix(run, layout.hub_speed, units),
          units));
      figures.push_back(std::move(figure));
    }
  } else {
    AddGroupedFigures(run, layout, t, layout.coordinates, "coordinates", "Generalized coordinates",
                      units, figures);
    AddGroupedFigures(run, layout, t, layout.speeds, "speeds", "Generalized speeds", units,
                      figures);
  }
  AddGroupedFigures(run, layout, t, layout.restoring, "restoring-forces", "Restoring forces",
                    units, figures);
  AddPhysicalFigures(run, layout, t, units, figures);
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
                                    const GnuplotOptions& options, const PlotUnits& units) {
  return RenderFigures(MakeRunFigures(run, units), out_dir, options);
}

std::string DefaultPlotDir(const std::string& csv_path) {
  const std::filesystem::path path(csv_path);
  return (path.parent_path() / (path.stem().string() + "-figures")).string();
}

}  // namespace hybridtest::report
