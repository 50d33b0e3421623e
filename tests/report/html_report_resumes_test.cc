// The report's "Resumes" section: one row per resume with its time, step, model time and
// force check; nothing for a run never resumed.
#include <gtest/gtest.h>

#include "hybridtest/report/html_report_resumes.h"

namespace hybridtest::report {
namespace {

TEST(HtmlReportResumes, OneRowPerResume) {
  const nlohmann::json sidecar = {
      {"resumes",
       {{{"time", "2026-11-23T00:01:46Z"}, {"step", 3637}, {"t", 3.637},
         {"previous_status", "running"},
         {"checks", {{{"slot", "r1"}, {"committed_force_N", 119.5}, {"force_N", 119.25},
                      {"tolerance_N", 100.0}}}}},
        {{"time", "2026-11-23T02:00:00Z"}, {"step", 5000}, {"t", 5.0},
         {"previous_status", "stopped: <lost bench>"}, {"checks", nlohmann::json::array()},
         {"refused", "force differs"}}}}};
  const std::string html = ResumesSection(sidecar);
  EXPECT_NE(html.find("2026-11-23T00:01:46Z"), std::string::npos) << html;
  EXPECT_NE(html.find("<td>3637</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("committed 119.5 N, measured 119.25 N"), std::string::npos) << html;
  EXPECT_NE(html.find("refused: force differs"), std::string::npos) << html;
  EXPECT_NE(html.find("&lt;lost bench&gt;"), std::string::npos) << html;  // escaped
  EXPECT_EQ(ResumesSection(nlohmann::json{{"status", "completed"}}), "");
}

// Issue 50: the operator's Hold and Continue were in the sidecar only.
TEST(HtmlReportResumes, TheOperatorsActionsAreListed) {
  const nlohmann::json sidecar = {
      {"operator_actions",
       {{{"action", "hold"}, {"origin", "127.0.0.1 (<browser>)"},
         {"asked_at", "2026-11-24T01:57:44Z"}, {"applied_at", "2026-11-24T01:57:45Z"},
         {"step", 10710}, {"t", 10.71}},
        {{"action", "continue"}, {"origin", "127.0.0.1"}, {"asked_at", "2026-11-24T01:58:00Z"},
         {"applied_at", "2026-11-24T01:58:00Z"}, {"step", 10710}, {"t", 10.71}}}}};
  const std::string html = OperatorActionsSection(sidecar);
  EXPECT_NE(html.find("<h2>Operator actions</h2>"), std::string::npos) << html;
  EXPECT_NE(html.find("<td>hold</td><td>10710</td><td>10.71</td><td>2026-11-24T01:57:44Z</td>"),
            std::string::npos) << html;
  EXPECT_NE(html.find("<td>continue</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("&lt;browser&gt;"), std::string::npos) << html;  // escaped
  EXPECT_EQ(OperatorActionsSection(nlohmann::json{{"status", "completed"}}), "");
}

}  // namespace
}  // namespace hybridtest::report
