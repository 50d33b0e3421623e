// hybridtest report RUN.csv [--against RUN_B.csv] [--out FILE.html] [--transient SECONDS]
// [--units mm,kN]:
// one self-contained HTML report (report/html_report.h). Default FILE: <CSV directory>/<run
// name>-report.html.
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/html_report.h"

namespace hybridtest::app {
namespace {

struct ReportOptions {
  std::string run_csv;
  std::string against_csv;
  std::string out_path;
  double transient = -1;  // [s]; < 0: 30 % of the run's duration
  std::string units;      // display units, e.g. "mm,kN"
};

void AddReportCommand(CLI::App& root) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* command = root.add_subcommand(
      "report", "Write a self-contained HTML report of a run: the result first (summary, limits "
                "used; with --against, the comparison's headline errors), then the figures, then "
                "configuration and model parameters");
  command->add_option("run", options->run_csv, "The run's CSV file, e.g. results/run.csv")
      ->required()
      ->check(RegularInputFile());
  command->add_option("--against", options->against_csv,
                      "Another run to compare with (e.g. the numerical simulation)")
      ->check(RegularInputFile());
  command->add_option("--out", options->out_path,
                      "HTML file to write (default: <CSV directory>/<run name>-report.html)");
  command->add_option("--transient", options->transient,
                      "With --against: initial transient excluded from means and amplitudes, in "
                      "seconds (default: 30 % of the run's duration)")
      ->check(NonNegativeFiniteNumber());
  command->add_option("--units", options->units,
                      "Display units of lengths and forces in figures and the summary, e.g. "
                      "mm,kN or length=mm,force=kN (default: SI, m and N)");
  command->callback([options] {
    report::HtmlReportOptions report_options;
    report_options.units = report::ParsePlotUnits(options->units);
    const std::string out =
        options->out_path.empty() ? report::DefaultReportPath(options->run_csv) : options->out_path;
    // Nothing a report reads (the runs, their companions, what they read) is written over.
    std::vector<io::ProtectedFile> inputs = io::RunProtectedFiles(options->run_csv);
    if (!options->against_csv.empty()) {
      const auto more = io::RunProtectedFiles(options->against_csv);
      inputs.insert(inputs.end(), more.begin(), more.end());
    }
    io::CheckOutputFile(out, inputs, "--out");
    const io::RunData run = LoadRunInput(options->run_csv, "run");
    for (const auto& w : run.warnings) fmt::print(stderr, "warning: {}\n", w);
    std::unique_ptr<io::RunData> against;
    if (!options->against_csv.empty()) {
      against = std::make_unique<io::RunData>(LoadRunInput(options->against_csv, "--against"));
      for (const auto& w : against->warnings) fmt::print(stderr, "warning: {}\n", w);
    }
    // Like `run`: the folders of --out are created.
    const auto parent = std::filesystem::path(out).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    report_options.transient = options->transient;
    report::WriteHtmlReport(run, against.get(), out, report_options);
    fmt::print("{}\n", out);
  });
}

const CommandRegistration kRegistration{"report", &AddReportCommand};

}  // namespace
}  // namespace hybridtest::app
