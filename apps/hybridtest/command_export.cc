// hybridtest export RUN.csv --hdf5 FILE.h5: a run (CSV + sidecar) as one HDF5 file, laid out
// as docs/results-format.md describes. Without --hdf5 the file goes beside the CSV (run.h5).
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "command.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/hdf5_export.h"

namespace hybridtest::app {
namespace {

struct ExportOptions {
  std::string run_csv;
  std::string h5_path;
};

void AddExportCommand(CLI::App& root) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* command = root.add_subcommand(
      "export", "Convert a run (CSV + .meta.json sidecar) to another format (HDF5)");
  command->add_option("run", options->run_csv, "The run's CSV file, e.g. results/run.csv")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--hdf5", options->h5_path,
                      "HDF5 file to write (default: the CSV's path with extension .h5)");
  command->callback([options] {
    std::string h5_path = options->h5_path;
    if (h5_path.empty()) {
      h5_path = std::filesystem::path(options->run_csv).replace_extension(".h5").string();
    }
    const io::RunData run = io::LoadRun(options->run_csv);
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

const CommandRegistration kRegistration{"export", &AddExportCommand};

}  // namespace
}  // namespace hybridtest::app
