// hybridtest plot RUN.csv [--out DIR] [--units mm,kN]: the run's figures as PNG and SVG (every
// coordinate, speed and restoring force of the model, named from the model; for each physical
// substructure its tracking, force, hysteresis and use of the limits; report/plot.h). Default
// DIR: <CSV directory>/<run name>-figures.
#include <fmt/core.h>

#include <memory>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/plot.h"

namespace hybridtest::app {
namespace {

struct PlotOptions {
  std::string run_csv;
  std::string out_dir;
  std::string units;
};

void AddPlotCommand(CLI::App& root) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* command = root.add_subcommand(
      "plot", "Draw a run's figures (PNG and SVG) with gnuplot, like the paper's Fig. 6");
  command->add_option("run", options->run_csv, "The run's CSV file, e.g. results/run.csv")
      ->required()
      ->check(RegularInputFile());
  command->add_option("--out", options->out_dir,
                      "Directory for the figures (default: <CSV directory>/<run name>-figures)");
  command->add_option("--units", options->units,
                      "Display units of lengths and forces, e.g. mm,kN or length=mm,force=kN "
                      "(default: SI, m and N)");
  command->callback([options] {
    const report::PlotUnits units = report::ParsePlotUnits(options->units);
    const std::string out_dir =
        options->out_dir.empty() ? report::DefaultPlotDir(options->run_csv) : options->out_dir;
    // The figures never replace a file of the run or one it read.
    io::CheckOutputDirectory(out_dir, io::RunProtectedFiles(options->run_csv), "--out", {},
                             {".png", ".svg"});
    const io::RunData run = LoadRunInput(options->run_csv, "run");
    for (const auto& warning : run.warnings) fmt::print(stderr, "warning: {}\n", warning);
    if (run.metadata.is_null()) {
      fmt::print(stderr,
                 "warning: {}: no sidecar; plain figures (no physical substructure known)\n",
                 io::SidecarPath(options->run_csv));
    }
    const auto files = report::WritePlots(run, out_dir, {}, units);
    for (const std::string& file : files) fmt::print("{}\n", file);
    if (files.empty()) {
      fmt::print(stderr, "warning: {}: no plottable channel; no figure written\n",
                 options->run_csv);
    }
  });
}

const CommandRegistration kCommandPlotRegistration{"plot", &AddPlotCommand};

}  // namespace
}  // namespace hybridtest::app
