// Figures of a model-file run (its own channel names) with two physical slots: a figure per
// coordinate group named from the model, distinct colours per physical slot, the tracking
// error, the force over time, the use of each limit (against a hand computation), and
// display units.
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/report/limit_use.h"
#include "hybridtest/report/plot.h"
#include "hybridtest/report/plot_units.h"
#include "report/plot_test_runs.h"

namespace hybridtest::report {
namespace {

constexpr int kRows = 401;
constexpr double kDt = 0.01;  // [s]

// A planar turbine-like run: x_t [m], psi [rad] (large), beta1, beta2 [rad] (small); slots r1,
// r2 [N·m] on beta1, beta2, both physical, with their actuator channels.
std::string WriteTurbineRun(const std::string& dir, const std::string& config) {
  std::vector<io::Channel> ch{{"t", "s", "time"},
                              {"x_t", "m", "tower-top displacement"},
                              {"psi", "rad", "rotor azimuth"},
                              {"beta1", "rad", "edgewise rotation of blade 1"},
                              {"beta2", "rad", "edgewise rotation of blade 2"},
                              {"v_t", "m/s", "tower-top velocity"},
                              {"w_r", "rad/s", "rotor speed"},
                              {"r1", "N\u00b7m", "root moment of blade 1"},
                              {"r2", "N\u00b7m", "root moment of blade 2"}};
  for (const char* slot : {"r1", "r2"}) {
    ch.push_back({std::string(slot) + "_command", "m", "command"});
    ch.push_back({std::string(slot) + "_position", "m", "position"});
    ch.push_back({std::string(slot) + "_force", "N", "force"});
  }
  Eigen::MatrixXd v(kRows, static_cast<Eigen::Index>(ch.size()));
  for (int r = 0; r < kRows; ++r) {
    const double t = r * kDt;
    v.row(r) << t, 0.02 * std::sin(t), 3.0 * t, 0.004 * std::sin(7 * t), 0.003 * std::cos(7 * t),
        0.02 * std::cos(t), 3.0, 800 * std::sin(7 * t), 600 * std::cos(7 * t),
        0.010 * std::sin(7 * t), 0.010 * std::sin(7 * t) + 1e-5, 120 * std::sin(7 * t),
        -0.008 * std::cos(5 * t), -0.008 * std::cos(5 * t) - 2e-5, 90 * std::cos(5 * t);
    if (r % 2 == 1) {  // substep rows of a multi-rate scheme: no specimen sample for r2
      for (int c = 12; c < 15; ++c) v(r, c) = NAN;
    }
  }
  nlohmann::json slots = nlohmann::json::array(), subs = nlohmann::json::array();
  for (int i = 1; i <= 2; ++i) {
    const std::string slot = fmt::format("r{}", i);
    slots.push_back({{"name", slot}, {"coordinate", fmt::format("beta{}", i)}, {"unit", "N\u00b7m"}});
    subs.push_back({{"slot", slot}, {"kind", "physical"}, {"description", "bench " + slot}});
  }
  nlohmann::json meta = {
      {"status", "completed"},
      {"config", config},
      {"model",
       {{"name", "wind_turbine"},
        {"coordinates", {{{"name", "x_t"}}, {{"name", "psi"}}, {{"name", "beta1"}},
                         {{"name", "beta2"}}}},
        {"speeds", {{{"name", "v_t"}}, {{"name", "w_r"}}}},
        {"slots", slots}}},
      {"substructures", subs}};
  const std::string path = dir + "/turbine.csv";
  testing::WriteRunFiles(path, ch, v, meta);
  return path;
}

const char* kConfig =
    "substructures:\n"
    "  r1: {type: physical, safety: {stroke_min: -0.05, stroke_max: 0.04, max_increment: 0.002,"
    " force_soft: 200, force_hard: 400}}\n"
    "  r2: {type: physical, safety: defaults}\n";

const PlotFigure* FindFigure(const std::vector<PlotFigure>& figures, const std::string& stem) {
  for (const PlotFigure& f : figures) {
    if (f.stem == stem) return &f;
  }
  return nullptr;
}

const PlotSeries* FindSeries(const PlotPanel& panel, const std::string& prefix) {
  for (const PlotSeries& s : panel.series) {
    if (s.label.rfind(prefix, 0) == 0) return &s;
  }
  return nullptr;
}

bool IsPhysicalColour(const std::string& colour) {
  const auto& p = PhysicalPalette();
  return std::find(p.begin(), p.end(), colour) != p.end();
}

TEST(ModelFileFigures, OneFigurePerCoordinateGroupNamedFromTheModel) {
  const testing::ScratchDir dir("plot-model-file");
  const io::RunData run = io::LoadRun(WriteTurbineRun(dir.path(), kConfig));
  const std::vector<PlotFigure> figures = MakeRunFigures(run);
  for (const char* stem : {"coordinates-x_t", "coordinates-psi", "coordinates-beta1-beta2",
                           "speeds-v_t", "speeds-w_r", "restoring-forces", "r1-command-position",
                           "r1-force-time", "r1-force-displacement", "r1-limits",
                           "r2-command-position", "r2-limits"}) {
    EXPECT_NE(FindFigure(figures, stem), nullptr) << stem;
  }
  // Physical slots: each its own warm colour, the others none of them.
  const PlotFigure* betas = FindFigure(figures, "coordinates-beta1-beta2");
  ASSERT_NE(betas, nullptr);
  const PlotSeries* b1 = FindSeries(betas->panels[0], "beta1");
  const PlotSeries* b2 = FindSeries(betas->panels[0], "beta2");
  ASSERT_TRUE(b1 && b2);
  EXPECT_EQ(b1->label, "beta1 (physical, r1)");
  EXPECT_NE(b1->color, b2->color);
  EXPECT_TRUE(IsPhysicalColour(b1->color) && IsPhysicalColour(b2->color));
  const PlotFigure* x_t = FindFigure(figures, "coordinates-x_t");
  EXPECT_FALSE(IsPhysicalColour(x_t->panels[0].series[0].color));
  EXPECT_NE(x_t->title.find("tower-top displacement"), std::string::npos);
  const PlotFigure* forces = FindFigure(figures, "restoring-forces");
  EXPECT_NE(FindSeries(forces->panels[0], "r1")->color, FindSeries(forces->panels[0], "r2")->color);
  EXPECT_EQ(forces->panels[0].y_label, "Restoring forces [N\u00b7m]");
}

TEST(ModelFileFigures, TrackingPanelIsMeasuredMinusCommand) {
  const testing::ScratchDir dir("plot-tracking");
  const io::RunData run = io::LoadRun(WriteTurbineRun(dir.path(), kConfig));
  const std::vector<PlotFigure> figures = MakeRunFigures(run);
  const PlotFigure* tracking = FindFigure(figures, "r1-command-position");
  ASSERT_NE(tracking, nullptr);
  ASSERT_EQ(tracking->panels.size(), 2u);
  const Eigen::VectorXd error = tracking->panels[1].series.at(0).y;
  EXPECT_NEAR(error.minCoeff(), 1e-5, 1e-12);
  EXPECT_NEAR(error.maxCoeff(), 1e-5, 1e-12);
}

TEST(ModelFileFigures, DisplayUnitsScaleValuesAndLabels) {
  const testing::ScratchDir dir("plot-units");
  const io::RunData run = io::LoadRun(WriteTurbineRun(dir.path(), kConfig));
  const auto si = MakeRunFigures(run);
  const auto lab = MakeRunFigures(run, ParsePlotUnits("mm,kN"));
  const PlotPanel& a = FindFigure(si, "coordinates-x_t")->panels[0];
  const PlotPanel& b = FindFigure(lab, "coordinates-x_t")->panels[0];
  EXPECT_NE(b.y_label.find("[mm]"), std::string::npos) << b.y_label;
  EXPECT_DOUBLE_EQ(b.series[0].y[100], 1000 * a.series[0].y[100]);
  const PlotPanel& f = FindFigure(lab, "r1-force-time")->panels[0];
  EXPECT_NE(f.y_label.find("[kN]"), std::string::npos) << f.y_label;
  EXPECT_DOUBLE_EQ(f.series[0].y[3], 0.12 * std::sin(7 * 3 * kDt));
  EXPECT_NE(FindFigure(lab, "restoring-forces")->panels[0].y_label.find("[kN\u00b7m]"),
            std::string::npos);
  // Angles are left as recorded.
  EXPECT_DOUBLE_EQ(FindFigure(lab, "coordinates-psi")->panels[0].series[0].y[10], 0.3);
}

TEST(PlotUnits, ParsesUnitsAndQuantities) {
  EXPECT_TRUE(ParsePlotUnits("").IsSi());
  const PlotUnits lab = ParsePlotUnits("mm, kN");
  EXPECT_EQ(lab.length, "mm");
  EXPECT_EQ(lab.force, "kN");
  EXPECT_DOUBLE_EQ(lab.Factor("N/m"), 1e-6);
  EXPECT_EQ(lab.Label("N/m"), "kN/mm");
  EXPECT_EQ(lab.Label("m/s"), "mm/s");
  EXPECT_DOUBLE_EQ(lab.Factor("rad"), 1.0);
  const PlotUnits named = ParsePlotUnits("force=MN,length=cm");
  EXPECT_EQ(named.force, "MN");
  EXPECT_EQ(named.length, "cm");
  for (const char* bad : {"inch", "force=mm", "speed=mm", "mm,lbf"}) {
    try {
      ParsePlotUnits(bad);
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("--units"), std::string::npos) << e.what();
    }
  }
}

TEST(LimitUse, MatchesAHandComputationOfEachLimit) {
  const testing::ScratchDir dir("limit-use");
  const io::RunData run = io::LoadRun(WriteTurbineRun(dir.path(), kConfig));
  PhysicalChannels r1{"r1", "beta1", "", "r1_command", "r1_position", "r1_force", "", "", -1};
  const std::vector<LimitUse> uses = CalcLimitUse(run, r1);
  ASSERT_EQ(uses.size(), 4u);
  // The oracle: the same quantities straight from the columns.
  const Eigen::VectorXd c = run.Get("r1_command"), f = run.Get("r1_force");
  double stroke = 0, increment = 0;
  for (Eigen::Index i = 0; i < c.size(); ++i) {
    stroke = std::max({stroke, c[i] / 0.04, c[i] / -0.05});
    if (i > 0) increment = std::max(increment, std::abs(c[i] - c[i - 1]) / 0.002);
  }
  const double force = f.cwiseAbs().maxCoeff();
  EXPECT_EQ(uses[0].limit, "stroke");
  EXPECT_DOUBLE_EQ(uses[0].peak, stroke);
  EXPECT_EQ(uses[1].limit, "max_increment");
  EXPECT_DOUBLE_EQ(uses[1].peak, increment);
  EXPECT_DOUBLE_EQ(uses[2].peak, force / 200);
  EXPECT_DOUBLE_EQ(uses[3].peak, force / 400);
  // `safety: defaults` gives the defaults; NaN rows of a sparse channel are skipped.
  PhysicalChannels r2{"r2", "beta2", "", "r2_command", "r2_position", "r2_force", "", "", -1};
  const auto defaults = CalcLimitUse(run, r2);
  ASSERT_EQ(defaults.size(), 4u);
  EXPECT_DOUBLE_EQ(defaults[3].peak, 90.0 / transfer::SafetyLimits{}.force_hard);
  EXPECT_EQ(defaults[3].t.size(), (kRows + 1) / 2);
}

TEST(LimitUse, TheSidecarsOwnLimitsWinOverTheConfigText) {
  const testing::ScratchDir dir("limit-sidecar");
  io::RunData run = io::LoadRun(WriteTurbineRun(dir.path(), kConfig));
  run.metadata["substructures"][0]["safety"] = {{"force_hard", 1000.0}};
  const auto limits = FindSlotLimits(run, "r1");
  ASSERT_TRUE(limits.has_value());
  EXPECT_EQ(limits->force_hard, 1000.0);
  EXPECT_EQ(limits->stroke_max, transfer::SafetyLimits{}.stroke_max);
  EXPECT_FALSE(FindSlotLimits(run, "r9").has_value());
}

}  // namespace
}  // namespace hybridtest::report
