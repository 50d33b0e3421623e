// The monitor's data side: the margins of the meters, the bounded history and the incremental series.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "hybridtest/monitor/monitor_state.h"

namespace hybridtest::monitor {
namespace {

TEST(Margin, NormalNearAndTrippedFromTheLimits) {
  transfer::SafetyLimits l;  // stroke ±0.15 m, force soft 8 kN, hard 10 kN
  EXPECT_EQ(CalcMargin(l, 0.0, 1000.0).level, "normal");
  EXPECT_DOUBLE_EQ(CalcMargin(l, 0.0, -1000.0).force_fraction, 0.1);
  EXPECT_EQ(CalcMargin(l, 0.0, 8500.0).level, "near");           // past force_soft
  EXPECT_EQ(CalcMargin(l, 0.13, 0.0).level, "near");             // 87 % of the stroke
  EXPECT_DOUBLE_EQ(CalcMargin(l, -0.075, 0.0).stroke_fraction, 0.5);
  EXPECT_EQ(CalcMargin(l, 0.0, -10000.0).level, "tripped");
  EXPECT_EQ(CalcMargin(l, 0.15, 0.0).level, "tripped");
  l.stroke_min = 0.0;  // an asymmetric stroke: the fraction is from its middle
  l.stroke_max = 0.2;
  EXPECT_DOUBLE_EQ(CalcMargin(l, 0.1, 0.0).stroke_fraction, 0.0);
}

void DescribeOneSlot(MonitorState& state) {
  RunIdentity id;
  id.slots = {"r1"};
  id.end_time = 10.0;
  state.SetIdentity(id, FrameLayout{1, 1}, {{"r1", "r1", 0, {"r1"}, transfer::SafetyLimits{}, 0.02}});
}

std::vector<double> Frame(long step) {
  // step, t, wall, lab, evaluations, d, r, command, position, force
  const double t = 0.001 * static_cast<double>(step);
  return {double(step), t, t, 2 * t, double(2 * step), 0.1 * t, 7.0 * t, 0.02 + t, 0.02 + t, 5.0 * t};
}

TEST(MonitorState, TheStateShowsTheLatestFrameAndTheMeters) {
  MonitorState state(100);
  DescribeOneSlot(state);
  EXPECT_EQ(state.StateJson()["status"], "starting");
  for (long s = 0; s <= 500; ++s) state.AddFrame(Frame(s));
  const nlohmann::json j = state.StateJson();
  EXPECT_EQ(j["status"], "running");
  EXPECT_EQ(j["step"], 500);
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), 0.5);
  EXPECT_EQ(j["physical_evaluations"], 1000);
  EXPECT_DOUBLE_EQ(j["fraction"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(j["actuators"][0]["force"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(j["actuators"][0]["limits"]["force_hard"].get<double>(), 10e3);
  EXPECT_DOUBLE_EQ(j["actuators"][0]["margin"]["force_fraction"].get<double>(), 2.5e-4);
  EXPECT_FALSE(j["realtime"]["available"].get<bool>());
  // Simulated time runs as fast as wall time in these frames: the ETA is the time left.
  EXPECT_NEAR(j["eta_s"].get<double>(), 9.5, 1e-9);
  state.SetStatus("stopped", "interrupted", "hybridtest resume x.csv");
  EXPECT_EQ(state.StateJson()["resume_command"], "hybridtest resume x.csv");
}

TEST(MonitorState, TheHistoryStaysBoundedAndCoversTheWholeRun) {
  MonitorState state(64);
  DescribeOneSlot(state);
  for (long s = 0; s < 10000; ++s) state.AddFrame(Frame(s));
  const nlohmann::json series = state.SeriesJson(-1, -1);
  const auto& t = series["columns"]["t"];
  EXPECT_LT(t.size(), 64u);
  EXPECT_GT(t.size(), 16u);
  EXPECT_DOUBLE_EQ(t.front().get<double>(), 0.0);
  EXPECT_GT(t.back().get<double>(), 9.0 * 0.9);  // the end of the run is there
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_GT(t[i].get<double>(), t[i - 1].get<double>());
  EXPECT_EQ(series["columns"]["r0"].size(), t.size());
}

TEST(MonitorState, TheSeriesIsIncrementalWithinAGeneration) {
  MonitorState state(1000);
  DescribeOneSlot(state);
  for (long s = 0; s < 10; ++s) state.AddFrame(Frame(s));
  const nlohmann::json first = state.SeriesJson(-1, -1);
  ASSERT_EQ(first["columns"]["seq"].size(), 10u);
  for (long s = 10; s < 15; ++s) state.AddFrame(Frame(s));
  const nlohmann::json next = state.SeriesJson(9, first["generation"].get<long>());
  EXPECT_FALSE(next["reset"].get<bool>());
  EXPECT_EQ(next["columns"]["seq"], (nlohmann::json{10, 11, 12, 13, 14}));
  // Another generation (the history was thinned since): everything again.
  EXPECT_TRUE(state.SeriesJson(9, first["generation"].get<long>() + 1)["reset"].get<bool>());
}

}  // namespace
}  // namespace hybridtest::monitor
