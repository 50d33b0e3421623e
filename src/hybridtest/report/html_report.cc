#include "hybridtest/report/html_report.h"

#include <fmt/core.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/report/compare.h"
#include "hybridtest/report/compare_plot.h"
#include "hybridtest/report/html_report_rths.h"
#include "hybridtest/report/html_report_resumes.h"
#include "hybridtest/report/html_report_style.h"
#include "hybridtest/report/html_report_summary.h"
#include "hybridtest/report/html_report_text.h"
#include "hybridtest/report/plot.h"
#include "hybridtest/report/plot_layout.h"

namespace hybridtest::report {
namespace {

using nlohmann::json;

std::string E(std::string_view text) { return EscapeHtml(text); }

// A member of a JSON object, or null.
json Member(const json& object, const char* key) {
  return object.is_object() && object.contains(key) ? object[key] : json();
}

// A temporary directory, removed with its contents when this goes out of scope.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "hybridtest-report-XXXXXX");
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw IoError("cannot create a temporary directory for the report's figures in " +
                    std::filesystem::temp_directory_path().string() + "; check TMPDIR");
    }
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Renders the figures as PNG and returns them as <figure> elements with data URIs.
std::string EmbedFigures(const std::vector<PlotFigure>& figures, const GnuplotOptions& base) {
  if (figures.empty()) return "<p class=\"note\">No figures: the run has no plottable channels.</p>\n";
  GnuplotOptions options = base;
  options.script.png = true;
  options.script.svg = false;
  options.script.width_px = 1080;  // the page's content width, so images are not rescaled
  TempDir dir;
  const std::vector<std::string> files = RenderFigures(figures, dir.path(), options);
  std::string html;
  for (std::size_t i = 0; i < files.size() && i < figures.size(); ++i) {
    std::ifstream in(files[i], std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    html += fmt::format(
        "<figure><img alt=\"{0}\" src=\"data:image/png;base64,{1}\"><figcaption>{0}</figcaption>"
        "</figure>\n",
        E(figures[i].title), EncodeBase64(bytes.str()));
  }
  return html;
}

// A two-column table of label → value rows; values are already HTML.
std::string KeyValueTable(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::string html = "<table class=\"kv\">\n";
  for (const auto& [key, value] : rows) {
    html += "<tr><th>" + E(key) + "</th><td>" + value + "</td></tr>\n";
  }
  return html + "</table>\n";
}

// Statistics the summary does not show (initial_stiffness has its own table).
std::string FurtherStatistics(const io::RunData& run) {
  const json stats = Member(run.metadata, "statistics");
  if (!stats.is_object()) return "";
  static const std::vector<std::string> kShown{
      "steps", "physical_evaluations", "wall_time_s", "lab_time_s", "slowdown", "rows",
      "sim_time_s", "stop", "initial_stiffness"};
  std::vector<std::pair<std::string, std::string>> rows;
  for (const auto& [key, value] : stats.items()) {
    if (std::find(kShown.begin(), kShown.end(), key) != kShown.end()) continue;
    rows.push_back({key, E(FormatJson(value))});
  }
  return rows.empty() ? "" : "<h3>Further statistics</h3>\n" + KeyValueTable(rows);
}

std::string ConfigurationSection(const io::RunData& run, const RunLayout& layout,
                                 const PlotUnits& units) {
  const json& meta = run.metadata;
  std::vector<std::pair<std::string, std::string>> rows;
  rows.push_back({"Model", E(layout.model_name.empty() ? "unknown" : layout.model_name)});
  for (const char* key : {"command", "config_path", "software_version", "start_time",
                          "finish_time"}) {
    const json v = Member(meta, key);
    if (!v.is_null() && !FormatJson(v).empty()) rows.push_back({key, E(FormatJson(v))});
  }
  std::string html = "<section id=\"configuration\"><h2>Configuration</h2>\n" + KeyValueTable(rows);

  // Substructures: which restoring forces are measured and which computed.
  const json subs = Member(meta, "substructures");
  if (subs.is_array() && !subs.empty()) {
    html += "<h3>Substructures</h3>\n<table><tr><th>slot</th><th>kind</th><th>coordinate</th>"
            "<th>description</th></tr>\n";
    for (const json& s : subs) {
      const std::string kind = FormatJson(Member(s, "kind"));
      const auto found = layout.slot_coordinates.find(FormatJson(Member(s, "slot")));
      const std::string coordinate = found == layout.slot_coordinates.end() ? "" : found->second;
      html += fmt::format("<tr><td>{}</td><td{}>{}</td><td>{}</td><td>{}</td></tr>\n",
                          E(FormatJson(Member(s, "slot"))),
                          kind == "physical" ? " class=\"physical\"" : "", E(kind), E(coordinate),
                          E(FormatJson(Member(s, "description"))));
    }
    html += "</table>\n";
  }
  html += InitialStiffnessSection(run, units);
  html += FurtherStatistics(run);
  const json config = Member(meta, "config");
  if (config.is_string() && !config.get<std::string>().empty()) {
    html += "<details open><summary>Configuration file (verbatim)</summary><pre>" +
            E(config.get<std::string>()) + "</pre></details>\n";
  } else if (!meta.is_object()) {
    html += "<p class=\"note\">No sidecar (" + E(io::SidecarPath(run.csv_path)) +
            "): configuration, model and statistics are unknown.</p>\n";
  }
  return html + "</section>\n";
}

std::string ParametersSection(const io::RunData& run) {
  const json params = Member(Member(run.metadata, "model"), "parameters");
  std::string html = "<section id=\"parameters\"><h2>Model parameters</h2>\n";
  if (!params.is_array() || params.empty()) {
    return html + "<p class=\"note\">The sidecar lists no model parameters.</p></section>\n";
  }
  html += "<table><tr><th>name</th><th>value</th><th>unit</th><th>description</th></tr>\n";
  for (const json& p : params) {
    html += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td>{}</td><td>{}</td></tr>\n",
                        E(FormatJson(Member(p, "name"))), E(FormatJson(Member(p, "value"))),
                        E(FormatJson(Member(p, "unit"))), E(FormatJson(Member(p, "description"))));
  }
  return html + "</table></section>\n";
}

std::string ComparisonSection(const io::RunData& run, const io::RunData& against,
                              const ComparisonTable& table, const HtmlReportOptions& options) {
  std::string html = "<section id=\"comparison\"><h2>Comparison: " + E(table.name_a) +
                     " against " + E(table.name_b) + "</h2>\n";
  html += fmt::format(
      "<p class=\"note\">A = {} ({}), B = {} ({}). Differences A&minus;B at {} of A&rsquo;s time "
      "points ({} with B interpolated linearly, the rest exact). Mean and amplitude "
      "(half of max&minus;min) after the first {} s.</p>\n",
      E(table.name_a), E(table.path_a), E(table.name_b), E(table.path_b), table.compared_points,
      table.interpolated_points, E(FormatNumber(table.transient)));
  html += "<table><tr><th>channel</th><th>unit</th><th>max |A&minus;B|</th><th>RMS(A&minus;B)</th>"
          "<th>mean A</th><th>amplitude A</th><th>mean B</th><th>amplitude B</th></tr>\n";
  for (const ChannelComparison& row : table.rows) {
    html += "<tr><td>" + E(row.channel) + "</td><td>" + E(row.unit) + "</td>";
    for (double v : {row.max_abs_diff, row.rms_diff, row.mean_a, row.amplitude_a, row.mean_b,
                     row.amplitude_b}) {
      html += "<td class=\"num\">" + (std::isnan(v) ? "&ndash;" : E(FormatNumber(v))) + "</td>";
    }
    html += "</tr>\n";
  }
  html += "</table>\n<h3>Overlay figures</h3>\n";
  html += EmbedFigures(MakeComparisonFigures(run, against), options.gnuplot);
  return html + "</section>\n";
}

std::string ChannelsSection(const io::RunData& run) {
  std::string html = "<section id=\"channels\"><details><summary>Channels (" +
                     std::to_string(run.channels.size()) + ")</summary>\n"
                     "<table><tr><th>name</th><th>unit</th><th>description</th></tr>\n";
  for (const io::Channel& c : run.channels) {
    html += "<tr><td>" + E(c.name) + "</td><td>" + E(c.unit) + "</td><td>" + E(c.description) +
            "</td></tr>\n";
  }
  return html + "</table></details></section>\n";
}

}  // namespace

std::string MakeHtmlReport(const io::RunData& run, const io::RunData* against,
                           const HtmlReportOptions& options) {
  const RunLayout layout = DescribeRun(run);
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                     "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<title>hybridtest report: " + E(layout.name) + "</title>\n<style>" + kHtmlReportCss +
          "</style>\n</head>\n<body>\n";
  html += "<header class=\"top\"><div><h1>Run report: " + E(layout.name) + "</h1><p>" +
          E(run.csv_path) + (layout.model_name.empty() ? "" : " &middot; model " +
          E(layout.model_name)) + "</p></div></header>\n<main>\n";
  // The result first: the summary, then the figures, then how the run was made.
  std::unique_ptr<ComparisonTable> comparison;
  if (against != nullptr) {
    const double transient = options.transient >= 0 ? options.transient : DefaultTransient(run);
    comparison = std::make_unique<ComparisonTable>(CompareRuns(run, *against, transient));
  }
  html += SummarySection(run, layout, comparison.get(), options.units);
  html += "<section id=\"figures\"><h2>Figures</h2>\n";
  if (!layout.physical.empty()) {
    html += "<p class=\"note\">Physical substructures are drawn thick, each in its own warm "
            "colour (the first in <span class=\"physical\">red</span>).</p>\n";
  }
  html += EmbedFigures(MakeRunFigures(run, options.units), options.gnuplot) + "</section>\n";
  html += RthsSection(run, against);
  if (comparison) html += ComparisonSection(run, *against, *comparison, options);
  html += ConfigurationSection(run, layout, options.units);
  html += ParametersSection(run);
  if (!options.equations.empty()) {
    html += "<section id=\"equations\"><h2>Equations of motion</h2>\n<p class=\"note\">"
            "Derived by the engine itself on a symbolic scalar from " +
            E(options.equations_source) + " (<code>hybridtest equations</code>; "
            "docs/equations.md).</p>\n<pre>" + E(options.equations) + "</pre></section>\n";
  }
  html += ResumesSection(run.metadata);
  html += OperatorActionsSection(run.metadata);
  html += ChannelsSection(run);
  html += std::string("<footer>Generated by hybridtest ") + E(kVersion) +
          ". Self-contained: figures are embedded; nothing is loaded from the network.</footer>\n";
  return html + "</main>\n</body>\n</html>\n";
}

void WriteHtmlReport(const io::RunData& run, const io::RunData* against,
                     const std::string& out_path, const HtmlReportOptions& options) {
  const std::string html = MakeHtmlReport(run, against, options);
  std::ofstream out(out_path, std::ios::binary);
  out << html;
  out.flush();
  if (!out) {
    throw IoError("cannot write the report to " + out_path +
                  "; check that the directory exists and is writable");
  }
}

std::string DefaultReportPath(const std::string& csv_path) {
  const std::filesystem::path path(csv_path);
  return (path.parent_path() / (path.stem().string() + "-report.html")).string();
}

}  // namespace hybridtest::report
