#pragma once
// Turns figures (plot_figure.h) into one gnuplot script. Pure text generation: nothing is run
// and nothing is written here (gnuplot.h does that).
//
// The script holds every line's samples as an inline datablock ($D0, $D1, ...), decimated with
// SelectPlotSamples (plot_decimate.h), and then draws each figure once per requested terminal:
// pngcairo → <out_dir>/<stem>.png and svg → <out_dir>/<stem>.svg. Text is set with
// `noenhanced`, so channel names such as r1_force are printed literally. A figure with several
// panels is a vertical multiplot whose height grows with the number of panels.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "hybridtest/report/plot_decimate.h"
#include "hybridtest/report/plot_figure.h"

namespace hybridtest::report {

struct GnuplotScriptOptions {
  bool png = true;                          // write <stem>.png (pngcairo)
  bool svg = true;                          // write <stem>.svg
  int width_px = 1000;                      // image width. Unit: [px]
  int panel_height_px = 440;                // height of a single-panel figure. Unit: [px]
  int stacked_panel_height_px = 300;        // height per panel of a multiplot. Unit: [px]
  Eigen::Index max_points = kMaxPlotPoints; // decimation threshold per line. Unit: [samples]
};

// The script, and the files it will write (in order: for each figure, png then svg).
struct GnuplotScript {
  std::string text;
  std::vector<std::string> outputs;
};

GnuplotScript MakeGnuplotScript(const std::vector<PlotFigure>& figures, const std::string& out_dir,
                                const GnuplotScriptOptions& options = {});

// A string as a gnuplot double-quoted string literal (quotes included; \ and " escaped,
// line breaks replaced by spaces).
std::string QuoteGnuplot(const std::string& text);

}  // namespace hybridtest::report
