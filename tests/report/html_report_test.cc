// The HTML report: self-contained, escaped, with the tables and the embedded figures.
#include "hybridtest/report/html_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>


#include "hybridtest/report/html_report_text.h"
#include "report/plot_test_runs.h"
#include "support/run_command.h"

namespace hybridtest::report {
namespace {

using testing::ScratchDir;
using testing::Slurp;

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++n;
  }
  return n;
}

TEST(EscapeHtml, ReplacesEveryMarkupCharacter) {
  EXPECT_EQ(EscapeHtml("<a href=\"x\">'&'</a>"),
            "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
}

TEST(EncodeBase64, MatchesRfc4648TestVectors) {
  EXPECT_EQ(EncodeBase64(""), "");
  EXPECT_EQ(EncodeBase64("f"), "Zg==");
  EXPECT_EQ(EncodeBase64("fo"), "Zm8=");
  EXPECT_EQ(EncodeBase64("foo"), "Zm9v");
  EXPECT_EQ(EncodeBase64("foob"), "Zm9vYg==");
  EXPECT_EQ(EncodeBase64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(EncodeBase64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(EncodeBase64(std::string("\xff\x00\x80", 3)), "/wCA");
}

TEST(FormatDuration, ShowsHoursForLongTests) {
  EXPECT_EQ(FormatDuration(22560), "22560 s (6 h 16 min)");
  EXPECT_EQ(FormatDuration(95), "95 s (1 min 35 s)");
  EXPECT_EQ(FormatDuration(0.25), "0.25 s");
}

TEST(WriteHtmlReport, IsSelfContainedEscapedAndHoldsTablesAndFigures) {
  const ScratchDir dir("html");
  testing::RotorRunSpec hybrid;
  hybrid.config = "model: rotor  # <script>alert('x')</script>\n";
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), hybrid));
  testing::RotorRunSpec numerical;
  numerical.name = "numerical";
  numerical.physical_r1 = false;
  numerical.q1_offset = 0;
  const io::RunData against = io::LoadRun(testing::WriteRotorRun(dir.path(), numerical));
  WriteHtmlReport(run, &against, dir / "report.html");
  const std::string html = Slurp(dir / "report.html");

  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  // Self-contained: no external asset of any kind.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  // Figures: 7 of the run (blades, hub, restoring forces; r1's tracking, force, loop and lab
  // time) + 2 overlays, each a PNG data URI with a real PNG inside.
  EXPECT_EQ(Count(html, "<img "), 9u);
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,iVBORw0KGgo"), 9u);
  // Every src= is a data URI (std::regex would overflow the stack on the long base64 text).
  for (std::size_t at = html.find("src=\""); at != std::string::npos;
       at = html.find("src=\"", at + 1)) {
    EXPECT_EQ(html.compare(at + 5, 22, "data:image/png;base64,"), 0);
  }
  // Escaped: the config's markup and the parameter description come out as text.
  EXPECT_NE(html.find("# &lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("blade &lt;stiffness&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(html.find("blade <stiffness>"), std::string::npos);
  // The parameter table, the statistics and the comparison.
  EXPECT_NE(html.find("<td>k_b</td><td class=\"num\">7200</td><td>N/m</td>"), std::string::npos);
  EXPECT_NE(html.find("6 h 16 min"), std::string::npos);
  EXPECT_NE(html.find("2260 \u00d7"), std::string::npos);
  EXPECT_NE(html.find("Physical evaluations</th><td>4000</td>"), std::string::npos);
  EXPECT_NE(html.find("Comparison: hybrid against numerical"), std::string::npos);
  EXPECT_NE(html.find("<td>q1</td><td>m</td>"), std::string::npos);
  EXPECT_NE(html.find("class=\"physical\">physical</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>r2</td><td>numerical</td><td>q2</td>"), std::string::npos);
}

TEST(WriteHtmlReport, RunWithoutSidecarStillReports) {
  const ScratchDir dir("html-plain");
  testing::RotorRunSpec spec;
  spec.sidecar = false;
  const io::RunData run = io::LoadRun(testing::WriteRotorRun(dir.path(), spec));
  const std::string html = MakeHtmlReport(run, nullptr);
  EXPECT_NE(html.find("No sidecar"), std::string::npos);
  EXPECT_NE(html.find("lists no model parameters"), std::string::npos);
  EXPECT_EQ(html.find("id=\"comparison\""), std::string::npos);
  // q1..q3 and q4, u1..u3 and u4 (their scales differ), the restoring forces.
  EXPECT_EQ(Count(html, "src=\"data:image/png;base64,"), 5u);
}

TEST(ReportCommand, WritesTheFileItPrints) {
  const ScratchDir dir("html-cli");
  const std::string csv = testing::WriteRotorRun(dir.path(), {});
  const std::string command = fmt::format("'{}' report '{}' > '{}'", HYBRIDTEST_BINARY, csv,
                                          dir / "out.txt");
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(Slurp(dir / "out.txt"), DefaultReportPath(csv) + "\n");
  EXPECT_GT(Slurp(DefaultReportPath(csv)).size(), 20000u);
}

// `report --equations`: the equations of the model the run read, and only while its files are
// unchanged.
TEST(ReportCommand, IncludesTheRunsEquationsWhileItsFilesAreUnchanged) {
  const ScratchDir dir("html-equations");
  const std::string config = dir / "rotor.yaml";
  {
    std::ofstream out(config);
    out << "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
           "duration: 0.01\n";
  }
  const std::string csv = dir / "run.csv";
  const std::string bin = HYBRIDTEST_BINARY;
  auto [status, output] = hybridtest::testing::RunCommand(fmt::format("'{}' simulate '{}' --out '{}'", bin,
                                                          config, csv));
  ASSERT_EQ(status, 0) << output;
  const std::string html = dir / "report.html";
  std::tie(status, output) = hybridtest::testing::RunCommand(
      fmt::format("'{}' report '{}' --equations --out '{}'", bin, csv, html), 300);
  ASSERT_EQ(status, 0) << output;
  const std::string report = Slurp(html);
  ASSERT_NE(report.find("<section id=\"equations\"><h2>Equations of motion</h2>"),
            std::string::npos);
  const std::string equations = report.substr(report.find("<section id=\"equations\">"));
  // The rotor's parameters as symbols (m_b, l_b) and its four coordinates' equations.
  EXPECT_NE(equations.find("m_b"), std::string::npos);
  EXPECT_NE(equations.find("l_b"), std::string::npos);
  EXPECT_NE(equations.find("q4"), std::string::npos);
  // Without --equations: no such section.
  std::tie(status, output) = hybridtest::testing::RunCommand(
      fmt::format("'{}' report '{}' --out '{}'", bin, csv, dir / "plain.html"), 120);
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(Slurp(dir / "plain.html").find("id=\"equations\""), std::string::npos);
  // The config changed after the run: refused, naming it, and nothing is written.
  {
    std::ofstream out(config, std::ios::app);
    out << "# changed\n";
  }
  std::tie(status, output) = hybridtest::testing::RunCommand(
      fmt::format("'{}' report '{}' --equations --out '{}'", bin, csv, dir / "late.html"), 120);
  EXPECT_EQ(status, 2) << output;
  EXPECT_NE(output.find("rotor.yaml (config file): changed since the run started"),
            std::string::npos) << output;
  EXPECT_NE(output.find("hybridtest equations CONFIG"), std::string::npos) << output;
  EXPECT_FALSE(std::filesystem::exists(dir / "late.html"));
}

}  // namespace
}  // namespace hybridtest::report
