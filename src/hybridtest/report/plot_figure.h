#pragma once
// What a figure is, independent of how it is drawn: a file stem, a title and one or more panels
// stacked vertically, each with axis labels (units included in the text) and line series.
// gnuplot_script.h turns a list of these into one gnuplot script.
#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace hybridtest::report {

// One line in a panel. x and y have the same length (the samples, in time order).
struct PlotSeries {
  std::string label;              // legend entry, e.g. "q1 (physical)"
  Eigen::VectorXd x;              // (n × 1) abscissae, in the panel's x unit
  Eigen::VectorXd y;              // (n × 1) ordinates, in the panel's y unit
  std::string color = "#1f77b4";  // "#rrggbb"
  double line_width = 1.5;        // gnuplot line width (1 = thinnest)
  bool dashed = false;
};

// One set of axes.
struct PlotPanel {
  std::string title;    // panel title; for a single-panel figure the figure title is used
  std::string x_label;  // e.g. "time t [s]"
  std::string y_label;  // e.g. "blade-tip displacement [m]"
  bool x_is_time = true;  // x axis spans exactly the data (time); else a small margin is added
  std::vector<PlotSeries> series;
  // Vertical marks on a time axis (e.g. where a run was resumed): x in the panel's x unit
  // and a short label.
  std::vector<std::pair<double, std::string>> marks;
};

// One figure, written as <stem>.png and <stem>.svg.
struct PlotFigure {
  std::string stem;     // file name without extension, e.g. "displacements"
  std::string title;    // e.g. "Blade-tip displacements (run hybrid)"
  std::vector<PlotPanel> panels;
};

// Colours used across figures. Physical substructures are warm and thick (the first is red, as
// in the paper's Fig. 6a; each further physical slot its own colour); the palette for
// everything else contains none of them.
inline constexpr const char* kPhysicalColor = "#d62728";
inline constexpr double kPhysicalLineWidth = 3.0;
inline constexpr double kNormalLineWidth = 1.5;
inline const std::vector<std::string>& PhysicalPalette() {
  static const std::vector<std::string> palette{kPhysicalColor, "#ff7f0e", "#e377c2", "#8c564b",
                                                "#bcbd22"};
  return palette;
}
inline const std::vector<std::string>& NonPhysicalPalette() {
  static const std::vector<std::string> palette{"#1f77b4", "#2ca02c", "#9467bd", "#17becf",
                                                "#7f7f7f", "#393b79", "#637939", "#6b6ecf"};
  return palette;
}

}  // namespace hybridtest::report
