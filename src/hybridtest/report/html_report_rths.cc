// See html_report_rths.h.
#include "hybridtest/report/html_report_rths.h"

#include <fmt/format.h>

#include <cmath>

#include "hybridtest/report/html_report_text.h"
#include "hybridtest/report/rths_criteria.h"

namespace hybridtest::report {

std::string RthsSection(const io::RunData& run, const io::RunData* reference) {
  if (!IsRealTimeRun(run)) return "";
  auto E = [](const std::string& s) { return EscapeHtml(s); };
  std::string html = "<section id=\"rths\"><h2>Real-time criteria (vRTHS benchmark)</h2>\n";
  RthsCriteria c;
  std::string note;
  try {
    // Without a reference the run is its own: J1–J3 hold, J4–J9 say nothing (left out).
    c = ComputeRthsCriteria(run, reference != nullptr ? *reference : run);
  } catch (const std::exception& e) {
    return html + "<p class=\"note\">" + E(e.what()) + "</p></section>\n";
  }
  html += fmt::format(
      "<p class=\"note\">Slot {} over {} rows. J1 in ms, the others in % (NRMS = &sigma;(x&minus;y)"
      "/&sigma;(y), peak = max|x&minus;y|/max|y|). {}</p>\n",
      E(c.slot), c.points,
      reference != nullptr ? "Reference structure: " + E(reference->csv_path) + "."
                           : "J4&ndash;J9 need the reference structure (--against).");
  struct Row {
    int j;
    const char* what;
    std::string floor;
  };
  const Row rows[] = {{1, "tracking delay (cross-correlation of position and command)", ""},
                      {2, "NRMS tracking error", ""},
                      {3, "peak tracking error", ""},
                      {4, "NRMS error, floor 1 (measured)", c.floor[0]},
                      {5, "peak error, floor 1 (measured)", c.floor[0]},
                      {6, "NRMS error, floor 2", c.floor[1]},
                      {7, "NRMS error, floor 3", c.floor[2]},
                      {8, "peak error, floor 2", c.floor[1]},
                      {9, "peak error, floor 3", c.floor[2]}};
  html += "<table><tr><th>criterion</th><th>value</th><th>what</th><th>channel</th></tr>\n";
  for (const Row& r : rows) {
    if (r.j >= 4 && reference == nullptr) break;
    const double v = c.J[static_cast<std::size_t>(r.j)];
    html += fmt::format("<tr><td>J{}</td><td class=\"num\">{}</td><td>{}</td><td>{}</td></tr>\n",
                        r.j, std::isfinite(v) ? E(FormatNumber(v)) + (r.j == 1 ? " ms" : " %")
                                              : std::string("&ndash;"),
                        r.what, E(r.floor));
  }
  return html + "</table></section>\n";
}

}  // namespace hybridtest::report
