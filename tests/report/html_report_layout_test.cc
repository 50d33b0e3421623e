// The report leads with the result: the summary (status, evaluations and lab time, resumes,
// the comparison's headline errors, the limits used) before the figures, the figures before
// the configuration; numbers without float noise; K0 as a table; display units.
#include <gtest/gtest.h>

#include "hybridtest/report/html_report.h"
#include "hybridtest/report/html_report_text.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

using testing::ScratchDir;

const char* kConfig =
    "model: rotor\n"
    "substructures:\n"
    "  r1:\n"
    "    type: physical\n"
    "    safety: {stroke_min: -0.2, stroke_max: 0.2, max_increment: 0.01, force_soft: 500,"
    " force_hard: 520}\n";

io::RunData PhysicalRun(const std::string& dir, const std::string& name) {
  testing::RotorRunSpec spec;
  spec.name = name;
  spec.config = kConfig;
  io::RunData run = io::LoadRun(testing::WriteRotorRun(dir, spec));
  run.metadata["statistics"]["lab_time_s"] = 2.5140000000000002;
  run.metadata["statistics"]["initial_stiffness"] = {
      {{"slot", "r1"}, {"source", "measured"}, {"k0", 5267.153333333333},
       {"amplitude_m", 0.001}, {"samples_d_m_r_N", {{0.00025, 1.31646}, {0.0, -0.0116}}}},
      {{"slot", "r2"}, {"source", "law"}, {"k0", 7200.0}}};
  run.metadata["statistics"]["note_value"] = nlohmann::json::array({0.30000000000000004});
  run.metadata["resumes"] = {{{"t", 1.25}, {"step", 250}, {"time", "2026-01-01T00:00:00Z"}}};
  return run;
}

std::size_t At(const std::string& html, const std::string& what) {
  const std::size_t at = html.find(what);
  EXPECT_NE(at, std::string::npos) << what;
  return at;
}

TEST(HtmlReportLayout, SummaryThenFiguresThenConfiguration) {
  const ScratchDir dir("html-layout");
  const io::RunData run = PhysicalRun(dir.path(), "hybrid");
  testing::RotorRunSpec numerical;
  numerical.name = "numerical";
  numerical.physical_r1 = false;
  numerical.q1_offset = 0.0;
  const io::RunData against = io::LoadRun(testing::WriteRotorRun(dir.path(), numerical));
  const std::string html = MakeHtmlReport(run, &against);

  const std::size_t summary = At(html, "id=\"summary\"");
  const std::size_t figures = At(html, "id=\"figures\"");
  const std::size_t comparison = At(html, "id=\"comparison\"");
  const std::size_t configuration = At(html, "id=\"configuration\"");
  const std::size_t parameters = At(html, "id=\"parameters\"");
  EXPECT_LT(summary, figures);
  EXPECT_LT(figures, comparison);
  EXPECT_LT(comparison, configuration);
  EXPECT_LT(configuration, parameters);
  EXPECT_LT(At(html, "<section"), summary + 1);  // the summary is the first section

  // Inside the summary: status, evaluations, lab time, resumes, headline errors, limits.
  const std::string head = html.substr(summary, figures - summary);
  EXPECT_NE(head.find("badge ok\">completed"), std::string::npos);
  EXPECT_NE(head.find("Physical evaluations</th><td>4000</td>"), std::string::npos);
  EXPECT_NE(head.find("Lab time</th><td>2.514 s</td>"), std::string::npos);
  EXPECT_NE(head.find("Resumes</th><td>1 ("), std::string::npos);
  EXPECT_NE(head.find("Against numerical"), std::string::npos);
  // q1's headline error is the physical blade's offset, 0.02 m at the end (ramp → 1).
  EXPECT_NE(head.find("<tr><td>q1</td><td class=\"num\">0.02 m</td>"), std::string::npos);
  EXPECT_EQ(head.find("<tr><td>u1</td>"), std::string::npos);  // speeds: full table only
  EXPECT_NE(head.find("Safety limits used"), std::string::npos);
  EXPECT_NE(head.find("<td>force_hard</td><td class=\"num\">520 N</td>"), std::string::npos);
  EXPECT_NE(head.find("-0.2 m \u2026 0.2 m"), std::string::npos);

  // No float noise anywhere, K0 as a table, not as raw JSON.
  EXPECT_EQ(html.find("2.5140000000000002"), std::string::npos);
  EXPECT_EQ(html.find("0.30000000000000004"), std::string::npos);
  EXPECT_NE(html.find("[0.3]"), std::string::npos);
  EXPECT_EQ(html.find("samples_d_m_r_N"), std::string::npos);
  EXPECT_NE(html.find("<tr><td>r1</td><td>measured</td><td class=\"num\">5267 N/m</td>"
                      "<td class=\"num\">0.001 m</td><td class=\"num\">2</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td>r2</td><td>law</td><td class=\"num\">7200 N/m</td>"),
            std::string::npos);
}

TEST(HtmlReportLayout, LabUnitsInTheSummary) {
  const ScratchDir dir("html-units");
  const io::RunData run = PhysicalRun(dir.path(), "lab");
  HtmlReportOptions options;
  options.units = ParsePlotUnits("mm,kN");
  const std::string html = MakeHtmlReport(run, nullptr, options);
  EXPECT_NE(html.find("<td>force_hard</td><td class=\"num\">0.52 kN</td>"), std::string::npos);
  EXPECT_NE(html.find("-200 mm \u2026 200 mm"), std::string::npos);
  EXPECT_NE(html.find("0.005267 kN/mm"), std::string::npos);  // 5267 N/m
}

TEST(HtmlReportLayout, LimitNearlyReachedIsFlagged) {
  const ScratchDir dir("html-flag");
  const io::RunData run = PhysicalRun(dir.path(), "flag");
  const std::string html = MakeHtmlReport(run, nullptr);
  // |r1_force| peaks near 5250 · 0.1 + 20 = 545 N > 0.9 · 520 N.
  const std::size_t row = html.find("<td>force_hard</td>");
  ASSERT_NE(row, std::string::npos);
  EXPECT_NE(html.substr(row, 200).find("class=\"num bad\""), std::string::npos);
}

TEST(FormatJson, RoundsNestedNumbers) {
  EXPECT_EQ(FormatJson(nlohmann::json::parse(R"({"a":[2.5140000000000002,7]})")),
            R"({"a":[2.514,7]})");
  EXPECT_EQ(FormatDuration(0.330077287), "0.3301 s");
  EXPECT_EQ(FormatDuration(245.68), "245.7 s (4 min 6 s)");
}

}  // namespace
}  // namespace hybridtest::report
