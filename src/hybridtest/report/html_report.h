#pragma once
// One self-contained HTML report of a run: opens offline, with no external asset (inline CSS,
// figures as base64 PNG data URIs). Sections:
//   - header: run name, CSV path, model, status;
//   - run statistics: steps, physical evaluations, wall time, lab time, slowdown against real
//     time, status, simulated time span, and any further sidecar statistics;
//   - configuration: command, config path, software version, substructures (slot, kind,
//     coordinate, description), and the config file verbatim;
//   - model parameters: name, value, unit, description;
//   - figures of the run (plot.h);
//   - with `against`: the comparison table (compare.h) and the overlay figures (compare_plot.h);
//   - channels: name, unit, description.
// Every piece of text from the run is HTML-escaped.
#include <string>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/report/gnuplot.h"

namespace hybridtest::report {

struct HtmlReportOptions {
  double transient = -1;   // for the comparison; < 0: DefaultTransient(run). Unit: [s]
  GnuplotOptions gnuplot;  // png is forced on, svg off (figures are embedded as PNG)
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
