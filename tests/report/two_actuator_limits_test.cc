// The use of the safety limits of a specimen on two actuators that serves two slots (issue 38,
// item 3): one limit-use figure per actuator with that actuator's own limits (a scalar limit
// applies to every actuator, a list holds one per actuator), and the report's "Safety limits
// used" table naming each actuator's and each slot's limits, against hand computations.
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/report/html_report.h"
#include "hybridtest/report/limit_use.h"
#include "hybridtest/report/plot.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

constexpr int kRows = 201;
constexpr double kDt = 0.01;  // [s]

// Blade tip (q_flap, q_edge [m]; r_flap, r_edge [N]) on one specimen of two actuators.
std::string WriteTwoActuatorRun(const std::string& dir) {
  std::vector<io::Channel> ch{{"t", "s", "time"},          {"q_flap", "m", "flap"},
                              {"q_edge", "m", "edge"},     {"u1", "m/s", "flap rate"},
                              {"u2", "m/s", "edge rate"},  {"r_flap", "N", "flap force"},
                              {"r_edge", "N", "edge force"}};
  for (const char* a : {"blade1_a1", "blade1_a2"}) {
    ch.push_back({std::string(a) + "_command", "m", "command"});
    ch.push_back({std::string(a) + "_position", "m", "position"});
    ch.push_back({std::string(a) + "_force", "N", "force"});
  }
  Eigen::MatrixXd v(kRows, static_cast<Eigen::Index>(ch.size()));
  for (int r = 0; r < kRows; ++r) {
    const double t = r * kDt;
    const double flap = 0.04 * std::sin(3 * t), edge = 0.01 * std::cos(2 * t);
    v.row(r) << t, flap, edge, 0.12 * std::cos(3 * t), -0.02 * std::sin(2 * t), 300 * flap / 0.04,
        -100 * edge / 0.01, 0.02 + flap, 0.02 + flap, 250 * std::sin(3 * t), 0.03 + 0.6 * flap,
        0.03 + 0.6 * flap, 900 * std::cos(2 * t);
  }
  nlohmann::json channels = nlohmann::json::array();
  for (const char* a : {"blade1_a1", "blade1_a2"}) {
    const std::string p(a);
    channels.push_back({{"command", p + "_command"}, {"position", p + "_position"},
                        {"force", p + "_force"}});
  }
  nlohmann::json meta = {
      {"status", "completed"},
      {"config",
       "substructures:\n"
       "  blade1:\n"
       "    type: physical\n"
       "    slots: [r_flap, r_edge]\n"
       "    safety: {stroke_min: -0.10, stroke_max: 0.15, max_increment: 0.005,\n"
       "             force_soft: 2000, force_hard: [3000, 1800], timeout: 5,\n"
       "             slots: {max_displacement: [0.08, 0.02], max_force: [600, 400]}}\n"},
      {"model",
       {{"name", "blade_tip"},
        {"coordinates", {{{"name", "q_flap"}}, {{"name", "q_edge"}}}},
        {"speeds", {{{"name", "u1"}}, {{"name", "u2"}}}},
        {"slots",
         {{{"name", "r_flap"}, {"coordinate", "q_flap"}, {"unit", "N"}},
          {{"name", "r_edge"}, {"coordinate", "q_edge"}, {"unit", "N"}}}}}},
      {"substructures",
       {{{"slot", "blade1"},
         {"kind", "physical"},
         {"slots", {"r_flap", "r_edge"}},
         {"channels", channels},
         {"description", "two actuators"}}}}};
  const std::string path = dir + "/blade.csv";
  testing::WriteRunFiles(path, ch, v, meta);
  return path;
}

const LimitUse* Find(const std::vector<LimitUse>& uses, const std::string& limit) {
  for (const LimitUse& u : uses) {
    if (u.limit == limit) return &u;
  }
  return nullptr;
}

TEST(TwoActuatorLimits, EachActuatorIsMeasuredAgainstItsOwnLimits) {
  const testing::ScratchDir dir("two-actuator-limits");
  const io::RunData run = io::LoadRun(WriteTwoActuatorRun(dir.path()));
  const RunLayout layout = DescribeRun(run);
  ASSERT_EQ(layout.physical.size(), 2u);
  const auto a2 = FindActuatorLimits(run, "blade1", 1);
  ASSERT_TRUE(a2.has_value());
  EXPECT_EQ(a2->force_hard, 1800.0);  // the list's second value
  EXPECT_EQ(a2->force_soft, 2000.0);  // a scalar: every actuator
  EXPECT_EQ(FindActuatorLimits(run, "blade1", 0)->force_hard, 3000.0);
  EXPECT_FALSE(FindActuatorLimits(run, "blade9", 0).has_value());

  const std::vector<LimitUse> first = CalcLimitUse(run, layout.physical[0]);
  const std::vector<LimitUse> second = CalcLimitUse(run, layout.physical[1]);
  ASSERT_EQ(first.size(), 4u);
  ASSERT_EQ(second.size(), 4u);
  const Eigen::VectorXd f1 = run.Get("blade1_a1_force"), f2 = run.Get("blade1_a2_force");
  const Eigen::VectorXd c2 = run.Get("blade1_a2_command");
  EXPECT_DOUBLE_EQ(Find(first, "force_hard")->peak, f1.cwiseAbs().maxCoeff() / 3000.0);
  EXPECT_DOUBLE_EQ(Find(second, "force_hard")->peak, f2.cwiseAbs().maxCoeff() / 1800.0);
  EXPECT_DOUBLE_EQ(Find(second, "stroke")->peak, c2.maxCoeff() / 0.15);

  // Per slot: |q| against max_displacement, |r| against max_force.
  const std::vector<SlotLimitUse> slots = CalcSlotLimitUse(run, layout, "blade1");
  ASSERT_EQ(slots.size(), 4u);
  EXPECT_EQ(slots[0].slot, "r_flap");
  EXPECT_EQ(slots[0].use.limit, "max_displacement");
  EXPECT_DOUBLE_EQ(slots[0].use.peak, run.Get("q_flap").cwiseAbs().maxCoeff() / 0.08);
  EXPECT_EQ(slots[1].use.limit, "max_force");
  EXPECT_DOUBLE_EQ(slots[1].use.peak, run.Get("r_flap").cwiseAbs().maxCoeff() / 600.0);
  EXPECT_EQ(slots[3].slot, "r_edge");
  EXPECT_DOUBLE_EQ(slots[3].use.peak, run.Get("r_edge").cwiseAbs().maxCoeff() / 400.0);
  EXPECT_GT(slots[2].use.peak, 0.45);  // |q_edge| up to 0.01 m of 0.02 m
}

TEST(TwoActuatorLimits, OneLimitFigurePerActuatorAndATableOfEveryLimit) {
  const testing::ScratchDir dir("two-actuator-report");
  const io::RunData run = io::LoadRun(WriteTwoActuatorRun(dir.path()));
  const std::vector<PlotFigure> figures = MakeRunFigures(run);
  for (const char* stem : {"blade1_a1-limits", "blade1_a2-limits"}) {
    bool found = false;
    for (const PlotFigure& f : figures) found = found || f.stem == stem;
    EXPECT_TRUE(found) << stem;
  }
  const std::string html = MakeHtmlReport(run, nullptr);
  const auto at = html.find("Safety limits used");
  ASSERT_NE(at, std::string::npos);
  const std::string table = html.substr(at, html.find("</table>", at) - at);
  for (const char* who : {"<td>actuator 1 of blade1</td><td>force_hard</td><td class=\"num\">3000 N",
                          "<td>actuator 2 of blade1</td><td>force_hard</td><td class=\"num\">1800 N",
                          "<td>slot r_flap (blade1)</td><td>max_force</td><td class=\"num\">600 N",
                          "<td>slot r_edge (blade1)</td><td>max_displacement</td><td class=\"num\">0.02 m"}) {
    EXPECT_NE(table.find(who), std::string::npos) << who << "\n" << table;
  }
}

}  // namespace
}  // namespace hybridtest::report
