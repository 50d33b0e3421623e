#pragma once
// Runs gnuplot (Debian's gnuplot-nox; needs the pngcairo and svg terminals) as a child process
// on a generated script, and renders figures with it.
#include <string>
#include <vector>

#include "hybridtest/report/gnuplot_script.h"
#include "hybridtest/report/plot_figure.h"

namespace hybridtest::report {

struct GnuplotOptions {
  std::string program = "gnuplot";  // executable, looked up on PATH when it has no '/'
  GnuplotScriptOptions script;      // terminals, sizes, decimation
};

// Runs `program script_file` with the script written to a temporary file; gnuplot's stdout is
// discarded and its stderr captured. Throws IoError if gnuplot cannot be started (message says
// to install gnuplot-nox) or exits non-zero (message includes gnuplot's stderr).
void RunGnuplot(const std::string& script, const std::string& program = "gnuplot");

// Writes every figure into out_dir (created if missing) as <stem>.png and/or <stem>.svg, with
// one gnuplot run. Returns the paths written, in figure order. Throws IoError if out_dir cannot
// be created, gnuplot fails, or an expected output file is missing afterwards.
std::vector<std::string> RenderFigures(const std::vector<PlotFigure>& figures,
                                       const std::string& out_dir,
                                       const GnuplotOptions& options = {});

}  // namespace hybridtest::report
