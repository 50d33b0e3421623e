// See html_report_resumes.h.
#include "hybridtest/report/html_report_resumes.h"

#include <fmt/format.h>

#include "hybridtest/report/html_report_text.h"

namespace hybridtest::report {

std::string ResumesSection(const nlohmann::json& sidecar) {
  if (!sidecar.is_object() || !sidecar.contains("resumes") || !sidecar["resumes"].is_array() ||
      sidecar["resumes"].empty()) {
    return "";
  }
  auto E = [](const std::string& s) { return EscapeHtml(s); };
  std::string html =
      "<section id=\"resumes\"><h2>Resumes</h2>\n<table><tr><th>#</th><th>resumed at (UTC)</th>"
      "<th>from step</th><th>t [s]</th><th>previous status</th><th>force check</th></tr>\n";
  int index = 0;
  for (const auto& r : sidecar["resumes"]) {
    std::string checks;
    for (const auto& c : r.value("checks", nlohmann::json::array())) {
      checks += fmt::format("{}: committed {} N, measured {} N (tolerance {} N); ",
                            c.value("slot", "?"), FormatNumber(c.value("committed_force_N", 0.0)),
                            FormatNumber(c.value("force_N", 0.0)),
                            FormatNumber(c.value("tolerance_N", 0.0)));
    }
    if (r.contains("refused")) checks += "refused: " + r.value("refused", "");
    if (checks.empty()) checks = "no physical slot";
    html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                        "</tr>\n", ++index, E(r.value("time", "")), r.value("step", 0L),
                        E(FormatNumber(r.value("t", 0.0))), E(r.value("previous_status", "")),
                        E(checks));
  }
  return html + "</table>\n</section>\n";
}

std::string OperatorActionsSection(const nlohmann::json& sidecar) {
  if (!sidecar.is_object() || !sidecar.contains("operator_actions") ||
      !sidecar["operator_actions"].is_array() || sidecar["operator_actions"].empty()) {
    return "";
  }
  auto E = [](const std::string& s) { return EscapeHtml(s); };
  std::string html =
      "<section id=\"operator-actions\"><h2>Operator actions</h2>\n<table><tr><th>#</th>"
      "<th>action</th><th>at step</th><th>t [s]</th><th>asked at (UTC)</th><th>applied at "
      "(UTC)</th><th>from</th></tr>\n";
  int index = 0;
  for (const auto& a : sidecar["operator_actions"]) {
    if (!a.is_object()) continue;
    std::string origin = a.value("origin", "");
    if (a.contains("record_error")) {
      origin += " (not recorded at once: " + a.value("record_error", "") + ")";
    }
    html += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                        "<td>{}</td></tr>\n", ++index, E(a.value("action", "?")),
                        a.value("step", 0L), E(FormatNumber(a.value("t", 0.0))),
                        E(a.value("asked_at", "")), E(a.value("applied_at", "")), E(origin));
  }
  return html + "</table>\n</section>\n";
}

}  // namespace hybridtest::report
