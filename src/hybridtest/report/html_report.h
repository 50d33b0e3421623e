#pragma once
// One self-contained HTML report of a run: opens offline, with no external asset (inline CSS,
// figures as base64 PNG data URIs). It leads with the result; sections in order:
//   - header: run name, CSV path, model;
//   - summary (html_report_summary.h): status and stop, simulated time, steps, physical
//     evaluations, lab and wall time, slowdown, resumes; with `against`, the comparison's
//     headline errors; the peak use of each safety limit;
//   - figures of the run (plot.h), in the display units asked for;
//   - with `against`: the full comparison table (compare.h) and the overlay figures
//     (compare_plot.h);
//   - configuration: command, config path, software version, substructures (slot, kind,
//     coordinate, description), the K0 table, further statistics, the config file verbatim;
//   - model parameters: name, value, unit, description;
//   - the equations of motion, when given (options.equations; `report --equations`);
//   - resumes (when the run was resumed);
//   - channels: name, unit, description.
// Numbers are rounded to what they mean (html_report_text.h).
// Every piece of text from the run is HTML-escaped.
#include <string>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"
#include "hybridtest/report/plot_units.h"

namespace hybridtest::report {

struct HtmlReportOptions {
  double transient = -1;   // for the comparison; < 0: DefaultTransient(run). Unit: [s]
  GnuplotOptions gnuplot;  // png is forced on, svg off (figures are embedded as PNG)
  PlotUnits units;         // display units of figures and summary values (SI by default)
  // The run's equations of motion as text (`hybridtest equations --format markdown`, which
  // the report layer does not derive itself), and where they came from; empty: no section.
  std::string equations;
  std::string equations_source;
};

// The report as one HTML document.
std::string MakeHtmlReport(const io::RunData& run, const io::RunData* against,
                           const HtmlReportOptions& options = {});

// Writes MakeHtmlReport(run, against) to out_path. Throws IoError when it cannot be written.
void WriteHtmlReport(const io::RunData& run, const io::RunData* against,
                     const std::string& out_path, const HtmlReportOptions& options = {});

// Default report path: <CSV directory>/<run name>-report.html.
std::string DefaultReportPath(const std::string& csv_path);

}  // namespace hybridtest::report
