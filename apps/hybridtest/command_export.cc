// hybridtest export RUN.csv [--hdf5 FILE.h5] [--csv FILE.csv [--units mm,kN]]: a run (CSV +
// sidecar) as one HDF5 file, laid out as docs/results-format.md describes (without --hdf5 or
// --csv: beside the CSV, run.h5), and/or as a CSV with a units row for lab tools
// (report/csv_export.h), optionally in lab units.
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/report/csv_export.h"
#include "hybridtest/report/hdf5_export.h"

namespace hybridtest::app {
namespace {

struct ExportOptions {
  std::string run_csv;
  std::string h5_path;
  std::string csv_path;
  std::string units;
};

void AddExportCommand(CLI::App& root) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* command = root.add_subcommand(
      "export", "Convert a run (CSV + .meta.json sidecar) to another format: HDF5, or a CSV "
                "with a units row (optionally in lab units)");
  command->add_option("run", options->run_csv, "The run's CSV file, e.g. results/run.csv")
      ->required()
      ->check(RegularInputFile());
  command->add_option("--hdf5", options->h5_path,
                      "HDF5 file to write (default: the CSV's path with extension .h5)");
  command->add_option("--csv", options->csv_path,
                      "CSV to write with the channel names on line 1 and their units on line 2 "
                      "(for spreadsheets and lab tools)");
  command->add_option("--units", options->units,
                      "units of the --csv export, e.g. mm,kN (lengths m|cm|mm|um, forces "
                      "N|kN|MN; default SI)");
  command->callback([options] {
    if (!options->units.empty() && options->csv_path.empty()) {
      throw ConfigError("--units " + options->units + " applies to the --csv export only (the "
                        "HDF5 file keeps SI); add --csv FILE.csv");
    }
    std::string h5_path = options->h5_path;
    // Nothing the export reads (the run, its companions, what it read) is written over, and
    // neither output is a device or a FIFO: checked before anything is written.
    const std::vector<io::ProtectedFile> inputs = io::RunProtectedFiles(options->run_csv);
    if (!options->csv_path.empty()) io::CheckOutputFile(options->csv_path, inputs, "--csv");
    if (!h5_path.empty() || options->csv_path.empty()) {
      io::CheckOutputFile(
          h5_path.empty()
              ? std::filesystem::path(options->run_csv).replace_extension(".h5").string()
              : h5_path,
          inputs, "--hdf5");
    }
    if (!options->csv_path.empty() && !h5_path.empty() &&
        io::SameFile(options->csv_path, h5_path)) {
      throw ConfigError(fmt::format("--csv {} and --hdf5 {} name the same file; give two "
                                    "different files", options->csv_path, h5_path));
    }
    if (!options->csv_path.empty()) {
      const report::PlotUnits units = report::ParsePlotUnits(options->units);
      const io::RunData run = LoadRunInput(options->run_csv, "run");
      for (const auto& warning : run.warnings) fmt::print(stderr, "warning: {}\n", warning);
      report::ExportCsvWithUnits(run, options->csv_path, units);
      fmt::print("exported {} rows x {} channels with a units row to {}\n", run.num_rows(),
                 run.num_channels(), options->csv_path);
      if (h5_path.empty()) return;
    }
    if (h5_path.empty()) {
      h5_path = std::filesystem::path(options->run_csv).replace_extension(".h5").string();
    }
    const io::RunData run = LoadRunInput(options->run_csv, "run");
    for (const auto& warning : run.warnings) fmt::print(stderr, "warning: {}\n", warning);
    if (run.metadata.is_null()) {
      fmt::print(stderr, "warning: {}: no sidecar; units inferred from the channel names\n",
                 io::SidecarPath(options->run_csv));
    }
    report::ExportHdf5(run, h5_path);
    fmt::print("exported {} rows x {} channels to {}\n", run.num_rows(), run.num_channels(),
               h5_path);
  });
}

const CommandRegistration kCommandExportRegistration{"export", &AddExportCommand};

}  // namespace
}  // namespace hybridtest::app
