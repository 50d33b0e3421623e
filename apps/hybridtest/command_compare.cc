// hybridtest compare RUN_A RUN_B [--out DIR] [--transient SECONDS]: A against B, channel by
// channel (report/compare.h): the table on stdout, as DIR/comparison.csv, and overlay figures
// in DIR. Default DIR: <A's directory>/<A>-vs-<B>.
// A real-time run A against its reference structure B also gets the vRTHS benchmark's J1–J9
// (report/rths_criteria.h), printed and written as DIR/rths_criteria.json.
#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include "cli_values.h"
#include "command.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/output_guard.h"
#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/compare.h"
#include "hybridtest/report/compare_plot.h"
#include "hybridtest/report/rths_criteria.h"

namespace hybridtest::app {
namespace {

struct CompareOptions {
  std::string run_a, run_b;
  std::string out_dir;
  double transient = -1;  // [s]; < 0: 30 % of A's duration
};

void AddCompareCommand(CLI::App& root) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command = root.add_subcommand(
      "compare", "Compare two runs: table of differences, steady means and amplitudes, and "
                 "overlay figures (e.g. hybrid test against numerical simulation)");
  command->add_option("run_a", options->run_a, "Run A's CSV (e.g. the hybrid test)")
      ->required()
      ->check(RegularInputFile());
  command->add_option("run_b", options->run_b, "Run B's CSV (e.g. the numerical simulation)")
      ->required()
      ->check(RegularInputFile());
  command->add_option("--out", options->out_dir,
                      "Directory for comparison.csv and the figures (default: <A's "
                      "directory>/<A>-vs-<B>)");
  command->add_option("--transient", options->transient,
                      "Initial transient excluded from means and amplitudes, in seconds "
                      "(default: 30 % of A's duration)")
      ->check(NonNegativeFiniteNumber());
  command->callback([options] {
    const io::RunData a = LoadRunInput(options->run_a, "run_a");
    const io::RunData b = LoadRunInput(options->run_b, "run_b");
    for (const auto& w : a.warnings) fmt::print(stderr, "warning: {}\n", w);
    for (const auto& w : b.warnings) fmt::print(stderr, "warning: {}\n", w);
    const double transient =
        options->transient >= 0 ? options->transient : report::DefaultTransient(a);
    const report::ComparisonTable table = report::CompareRuns(a, b, transient);

    std::string out_dir = options->out_dir;
    if (out_dir.empty()) {
      const std::filesystem::path pa(options->run_a), pb(options->run_b);
      out_dir = (pa.parent_path() / (pa.stem().string() + "-vs-" + pb.stem().string())).string();
    }
    // The table and figures never replace a file of either run or one they read.
    std::vector<io::ProtectedFile> inputs = io::RunProtectedFiles(options->run_a, "run A");
    const auto more = io::RunProtectedFiles(options->run_b, "run B");
    inputs.insert(inputs.end(), more.begin(), more.end());
    io::CheckOutputDirectory(out_dir, inputs, "--out", {"comparison.csv", "rths_criteria.json"},
                             {".png", ".svg"});
    std::error_code error;
    std::filesystem::create_directories(out_dir, error);
    if (error) throw IoError("cannot create the directory " + out_dir + ": " + error.message());
    const std::string csv = (std::filesystem::path(out_dir) / "comparison.csv").string();
    report::WriteComparisonCsv(table, csv);
    fmt::print("{}\n", report::FormatComparisonText(table));
    fmt::print("table:   {}\n", csv);
    if (report::IsRealTimeRun(a)) {
      // A real-time run against its reference structure: the vRTHS benchmark's criteria.
      const report::RthsCriteria rths = report::ComputeRthsCriteria(a, b);
      const std::string json = (std::filesystem::path(out_dir) / "rths_criteria.json").string();
      std::ofstream(json) << report::ToJson(rths).dump(2) << "\n";
      fmt::print("\n{}criteria: {}\n", report::FormatRthsCriteria(rths), json);
    }
    for (const std::string& file : report::WriteComparisonPlots(a, b, out_dir)) {
      fmt::print("figure:  {}\n", file);
    }
  });
}

const CommandRegistration kCommandCompareRegistration{"compare", &AddCompareCommand};

}  // namespace
}  // namespace hybridtest::app
