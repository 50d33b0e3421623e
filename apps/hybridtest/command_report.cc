// hybridtest report RUN.csv [--against RUN_B.csv] [--out FILE.html] [--transient SECONDS]
// [--units mm,kN] [--equations]:
// one self-contained HTML report (report/html_report.h). Default FILE: <CSV directory>/<run
// name>-report.html. --equations adds the run's equations of motion, derived from the config
// and model files the run read (refused if they changed since).
#include <fmt/core.h>

#include <filesystem>
#include <memory>

#include "cli_values.h"
#include "command.h"
#include "equations_document.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_inputs.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/report/html_report.h"

namespace hybridtest::app {
namespace {

struct ReportOptions {
  std::string run_csv;
  std::string against_csv;
  std::string out_path;
  double transient = -1;  // [s]; < 0: 30 % of the run's duration
  std::string units;      // display units, e.g. "mm,kN"
  bool equations = false;  // include the equations of motion
};

// The run's config path, from the record of the files it read; refused (ConfigError) if the
// run has no record or any of those files changed since, so that the equations printed are
// the ones the run integrated.
std::string RecordedConfig(const io::RunData& run) {
  const nlohmann::json* inputs = nullptr;
  if (run.metadata.is_object() && run.metadata.contains("extra") &&
      run.metadata["extra"].is_object() && run.metadata["extra"].contains("inputs")) {
    inputs = &run.metadata["extra"]["inputs"];
  }
  if (inputs == nullptr || !inputs->is_array()) {
    throw ConfigError(fmt::format("--equations: {} has no record of the files the run read (no "
                                  "sidecar, or one written before the record existed); print "
                                  "the equations with `hybridtest equations CONFIG` instead",
                                  run.csv_path));
  }
  const std::string config = io::RecordedConfigPath(*inputs, run.csv_path);
  const io::RunSpec spec = io::LoadRunSpec(config);  // physical slots allowed: nothing moves
  io::CheckRunInputs(*inputs, spec, run.csv_path,
                     "--equations prints the equations of the model the run integrated, from "
                     "the files it read",
                     "Restore those files, or print the equations of the files as they are now "
                     "with `hybridtest equations CONFIG`");
  return config;
}

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
  command->add_flag("--equations", options->equations,
                    "Include the run's equations of motion (as `hybridtest equations` prints "
                    "them), derived from the config and model files the run read; refused if "
                    "any of them changed since the run");
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
    if (options->equations) {
      EquationsOptions equations;
      equations.model = RecordedConfig(run);
      report_options.equations = EquationsDocument(equations);
      report_options.equations_source = equations.model;
    }
    report::WriteHtmlReport(run, against.get(), out, report_options);
    fmt::print("{}\n", out);
  });
}

const CommandRegistration kCommandReportRegistration{"report", &AddReportCommand};

}  // namespace
}  // namespace hybridtest::app
