// The vRTHS benchmark's criteria J1–J9 (report/rths_criteria.h) on constructed runs whose
// values are known by hand: amplitude errors give NRMS = peak = the error's ratio, a constant
// offset has no NRMS but a peak, a pure shift is the delay, and the setup transform is undone.
#include "hybridtest/report/rths_criteria.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/report/html_report_rths.h"

namespace hybridtest::report {
namespace {

using Signal = std::function<double(double)>;

io::RunData MakeRun(const std::string& path, double dt, int n,
                    const std::vector<std::pair<std::string, Signal>>& signals,
                    nlohmann::json metadata = nullptr) {
  io::RunData run;
  run.csv_path = path;
  run.channels.push_back({"t", "s", "time"});
  for (const auto& [name, f] : signals) run.channels.push_back({name, "", ""});
  run.values.resize(n, static_cast<Eigen::Index>(run.channels.size()));
  for (int i = 0; i < n; ++i) {
    const double t = dt * i;
    run.values(i, 0) = t;
    for (std::size_t c = 0; c < signals.size(); ++c) {
      run.values(i, static_cast<Eigen::Index>(c + 1)) = signals[c].second(t);
    }
  }
  run.metadata = std::move(metadata);
  return run;
}

const double kPi = std::numbers::pi;
double Y1(double t) { return 0.01 * std::sin(2 * kPi * 1.5 * t); }
double Y2(double t) { return 0.02 * std::sin(2 * kPi * 1.5 * t + 0.3); }
double Y3(double t) { return 0.03 * std::cos(2 * kPi * 0.7 * t); }

nlohmann::json RealTimeMetadata() {
  return {{"model", {{"slots", {{{"name", "r1"}, {"coordinate", "q1"}}}}}},
          {"config", "real_time: {hold_after_misses: 0}\nsubstructures:\n  r1:\n"
                     "    setup: {p0: 0.5, sign: -1, scale: 2}\n"},
          {"statistics", {{"real_time", nlohmann::json::object()}}}};
}

TEST(RthsCriteria, KnownValuesOfAConstructedRunAgainstItsReference) {
  // The actuator: position = 1.1 × command (J2 = J3 = 10 %), its displacement back through the
  // setup (p0 0.5 m, sign −1, scale 2) is 0.95 × y1 (J4 = J5 = 5 %); floor 2 is offset by 0.1 of
  // its amplitude (J6 = 0, J8 = 10 %); floor 3 is 1.2 × (J7 = J9 = 20 %).
  auto command = [](double t) { return 0.5 - 2.0 * Y1(t) * 0.95 / 1.1; };
  auto position = [&](double t) { return 1.1 * command(t) - 0.1 * 0.5; };
  // position − 0.5 = 1.1·(0.5 − 1.9/1.1·Y1) − 0.55 = −1.9 Y1 → d_m = 0.95 Y1.
  const io::RunData run =
      MakeRun("rt.csv", 1.0 / 1024, 4096,
              {{"q1", Y1}, {"q2", [](double t) { return Y2(t) + 0.002; }},
               {"q3", [](double t) { return 1.2 * Y3(t); }}, {"r1_command", command},
               {"r1_position", position}},
              RealTimeMetadata());
  const io::RunData ref = MakeRun("ref.csv", 1.0 / 1024, 4096, {{"q1", Y1}, {"q2", Y2}, {"q3", Y3}});
  ASSERT_TRUE(IsRealTimeRun(run));
  EXPECT_FALSE(IsRealTimeRun(ref));
  const RthsCriteria c = ComputeRthsCriteria(run, ref);
  EXPECT_EQ(c.slot, "r1");
  EXPECT_EQ(c.floor[0], "q1");
  EXPECT_EQ(c.floor[1], "q2");
  EXPECT_EQ(c.floor[2], "q3");
  EXPECT_EQ(c.points, 4096);
  EXPECT_NEAR(c.J[1], 0.0, 1e-9);
  // position − command = 0.1·command − 0.05 = 0.1·(command − 0.5): 10 % of the command's
  // σ, but its peak against max|command| (≈ 0.5 + 0.0173) is 0.1·0.01727/0.51727.
  EXPECT_NEAR(c.J[2], 10.0, 1e-9);
  EXPECT_NEAR(c.J[3], 100.0 * 0.1 * 0.019 / 1.1 / (0.5 + 0.019 / 1.1), 1e-3);
  EXPECT_NEAR(c.J[4], 5.0, 1e-9);
  EXPECT_NEAR(c.J[5], 5.0, 1e-9);
  EXPECT_NEAR(c.J[6], 0.0, 1e-9);
  EXPECT_NEAR(c.J[7], 20.0, 1e-9);
  EXPECT_NEAR(c.J[8], 10.0, 1e-3);  // max|y2| as sampled
  EXPECT_NEAR(c.J[9], 20.0, 1e-9);
  const nlohmann::json j = ToJson(c);
  EXPECT_NEAR(j["J7"].get<double>(), 20.0, 1e-9);
  EXPECT_NE(FormatRthsCriteria(c).find("J9 = 20 %"), std::string::npos) << FormatRthsCriteria(c);
}

TEST(RthsCriteria, APureShiftIsTheTrackingDelay) {
  // The position lags the command by 6 ms (exactly 6 samples at 1 kHz).
  auto command = [](double t) { return 0.01 * std::sin(2 * kPi * 2.0 * t); };
  const io::RunData run = MakeRun(
      "rt.csv", 0.001, 3000,
      {{"q1", command}, {"q2", command}, {"q3", command}, {"r1_command", command},
       {"r1_position", [&](double t) { return command(t - 0.006); }}},
      RealTimeMetadata());
  const RthsCriteria c = ComputeRthsCriteria(run, run);
  EXPECT_NEAR(c.J[1], 6.0, 0.05);
  // The error of a shift by φ = 2π·2 Hz·6 ms: |x − y| = 2 sin(φ/2)·amplitude.
  const double phi = 2 * kPi * 2.0 * 0.006;
  EXPECT_NEAR(c.J[3], 100.0 * 2 * std::sin(phi / 2), 0.05);
}

TEST(RthsCriteria, ACoarserReferenceIsInterpolatedLinearly) {
  // Ramps are interpolated exactly: the reference at 2 ms, the run at 1 ms; 1.5 × the ramp.
  auto ramp = [](double t) { return 0.01 + 3.0 * t; };
  const io::RunData run = MakeRun(
      "rt.csv", 0.001, 1001,
      {{"q1", ramp}, {"q2", [&](double t) { return 1.5 * ramp(t); }}, {"q3", ramp},
       {"r1_command", ramp}, {"r1_position", ramp}},
      RealTimeMetadata());
  const io::RunData ref = MakeRun("ref.csv", 0.002, 501, {{"q1", ramp}, {"q2", ramp}, {"q3", ramp}});
  const RthsCriteria c = ComputeRthsCriteria(run, ref);
  EXPECT_EQ(c.points, 1001);
  EXPECT_NEAR(c.J[6], 50.0, 1e-9);
  EXPECT_NEAR(c.J[8], 50.0, 1e-9);
  EXPECT_NEAR(c.J[7], 0.0, 1e-9);
}

TEST(RthsCriteria, AReferenceWithoutTheFloorsIsRefusedNamingIt) {
  const io::RunData run = MakeRun("rt.csv", 0.001, 100,
                                  {{"q1", Y1}, {"q2", Y2}, {"r1_command", Y1}, {"r1_position", Y1}},
                                  RealTimeMetadata());
  const io::RunData ref = MakeRun("ref.csv", 0.001, 100, {{"q1", Y1}});
  try {
    ComputeRthsCriteria(run, ref);
    FAIL() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("q2"), std::string::npos) << e.what();
  }
  const io::RunData numerical = MakeRun("num.csv", 0.001, 100, {{"q1", Y1}});
  EXPECT_THROW(ComputeRthsCriteria(numerical, ref), IoError);
}

TEST(RthsCriteria, ASlotOnTwoCoordinatesIsMeasuredAgainstTheReferencesOwnSlot) {
  // A damper between q1 and q2: its stroke is no coordinate; floor 1 is the reference's own
  // r1_position (through its setup: p0 0.5 m, sign −1, scale 2), floors 2 and 3 are q1 and q2.
  nlohmann::json meta = RealTimeMetadata();
  meta["model"]["slots"][0].erase("coordinate");
  auto stroke = [](double t) { return Y2(t) - Y1(t); };
  const io::RunData run = MakeRun(
      "rt.csv", 0.001, 800,
      {{"q1", Y1}, {"q2", Y2}, {"r1_command", [&](double t) { return 0.5 - 2 * stroke(t); }},
       {"r1_position", [&](double t) { return 0.5 - 2 * 0.9 * stroke(t); }}},
      meta);
  const io::RunData ref = MakeRun(
      "ref.csv", 0.001, 800,
      {{"q1", Y1}, {"q2", [](double t) { return 1.3 * Y2(t); }},
       {"r1_position", [&](double t) { return 0.5 - 2 * stroke(t); }}},
      meta);
  const RthsCriteria c = ComputeRthsCriteria(run, ref);
  EXPECT_EQ(c.floor[0], "r1_position");
  EXPECT_EQ(c.floor[1], "q1");
  EXPECT_EQ(c.floor[2], "q2");
  EXPECT_NEAR(c.J[4], 10.0, 1e-9);  // d_m = 0.9 × the reference's stroke
  EXPECT_NEAR(c.J[5], 10.0, 1e-9);
  EXPECT_NEAR(c.J[6], 0.0, 1e-9);
  EXPECT_NEAR(c.J[7], 100.0 * 0.3 / 1.3, 1e-9);
}

TEST(RthsCriteria, TheReportShowsJ1ToJ3AloneAndJ4ToJ9AgainstTheReference) {
  auto y = [](double t) { return Y1(t); };
  const io::RunData run = MakeRun(
      "rt.csv", 0.001, 500,
      {{"q1", y}, {"q2", Y2}, {"q3", Y3}, {"r1_command", [](double t) { return 0.5 - 2 * Y1(t); }},
       {"r1_position", [](double t) { return 0.5 - 2 * 1.1 * Y1(t); }}},
      RealTimeMetadata());
  const io::RunData ref = MakeRun("ref.csv", 0.001, 500, {{"q1", Y1}, {"q2", Y2}, {"q3", Y3}});
  const std::string alone = RthsSection(run, nullptr);
  EXPECT_NE(alone.find("<td>J3</td>"), std::string::npos) << alone;
  EXPECT_EQ(alone.find("<td>J4</td>"), std::string::npos) << alone;
  const std::string against = RthsSection(run, &ref);
  EXPECT_NE(against.find("<td>J9</td>"), std::string::npos) << against;
  EXPECT_NE(against.find(">10 %<"), std::string::npos) << against;  // J4: d_m = 1.1 y1
  EXPECT_EQ(RthsSection(ref, &run), "");  // not a real-time run
}

}  // namespace
}  // namespace hybridtest::report
