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

// Colours used across figures. Physical substructures are red, as in the paper's Fig. 6a; the
// palette for everything else contains no red.
inline constexpr const char* kPhysicalColor = "#d62728";
inline constexpr double kPhysicalLineWidth = 3.0;
inline constexpr double kNormalLineWidth = 1.5;
inline const std::vector<std::string>& NonPhysicalPalette() {
  static const std::vector<std::string> palette{"#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e",
                                                "#17becf", "#8c564b", "#7f7f7f", "#bcbd22"};
  return palette;
}

}  // namespace hybridtest::report
