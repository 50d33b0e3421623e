#include "hybridtest/transfer/safety.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hybridtest::transfer {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Runs `action` and returns the SafetyStop it throws (fails the test if none).
template <typename Action>
SafetyStop CatchStop(Action action) {
  try {
    action();
  } catch (const SafetyStop& stop) {
    return stop;
  }
  ADD_FAILURE() << "expected a SafetyStop";
  return SafetyStop("none", 0, 0, 0, 0, {}, "");
}

SafetyMonitor MakeMonitor() {
  SafetyMonitor monitor(SafetyLimits{});
  monitor.SetStartPosition(0.0);
  monitor.SetInitialStiffness(5250.0);
  return monitor;
}

TEST(SafetyMonitor, AcceptsAnOrdinaryExchange) {
  SafetyMonitor monitor = MakeMonitor();
  EXPECT_NO_THROW(monitor.CheckCommand(0.001, 0, 0));
  EXPECT_NO_THROW(monitor.CheckMeasurement(0.001, 0.001, 5.25, 0, 0));
  EXPECT_DOUBLE_EQ(monitor.last_safe_command(), 0.001);
}

TEST(SafetyMonitor, StrokeLimitsNameLimitValueStepStageAndFix) {
  SafetyMonitor monitor(SafetyLimits{});  // no start position: no increment check
  auto stop = CatchStop([&] { monitor.CheckCommand(0.151, 7, 1); });
  EXPECT_EQ(stop.limit(), "stroke_max");
  EXPECT_DOUBLE_EQ(stop.value(), 0.151);
  EXPECT_DOUBLE_EQ(stop.limit_value(), 0.150);
  EXPECT_EQ(stop.step(), 7);
  EXPECT_EQ(stop.stage(), 1);
  EXPECT_THAT(stop.what(), AllOf(HasSubstr("stroke_max"), HasSubstr("step 7 stage 1"),
                                 HasSubstr("0.151"), HasSubstr("0.15"),
                                 HasSubstr("To proceed")));
  EXPECT_EQ(CatchStop([&] { monitor.CheckCommand(-0.2, 0, 0); }).limit(), "stroke_min");
  EXPECT_FALSE(monitor.has_safe_command());  // a refused command is never "safe"
}

TEST(SafetyMonitor, MaxIncrementFromLastAcceptedCommand) {
  SafetyMonitor monitor = MakeMonitor();
  monitor.CheckCommand(0.004, 0, 0);
  auto stop = CatchStop([&] { monitor.CheckCommand(0.0095, 0, 1); });
  EXPECT_EQ(stop.limit(), "max_increment");
  EXPECT_NEAR(stop.value(), 0.0055, 1e-15);
  EXPECT_DOUBLE_EQ(monitor.last_safe_command(), 0.004);  // hold target unchanged
  EXPECT_THAT(stop.what(), HasSubstr("holds at the last safe command 0.004 m"));
  EXPECT_NO_THROW(monitor.CheckCommand(0.0089, 0, 1));
}

TEST(SafetyMonitor, FirstCommandIncrementCheckedAgainstStartPosition) {
  SafetyMonitor monitor(SafetyLimits{});
  monitor.SetStartPosition(0.050);
  const SafetyStop stop = CatchStop([&] { monitor.CheckCommand(0.0, 0, 0); });
  EXPECT_EQ(stop.limit(), "max_increment");
  // A jump at the first command is a p0 or unit mismatch, never a step size.
  EXPECT_THAT(stop.what(), HasSubstr("The first command 0 m is 0.05 m from the start position"));
  EXPECT_THAT(stop.what(), HasSubstr("setup.p0"));
  EXPECT_THAT(stop.what(), HasSubstr("p0_mm / 1000"));
  EXPECT_THAT(stop.what(), ::testing::Not(HasSubstr("reduce the time step")));
}

TEST(SafetyMonitor, LaterIncrementsKeepTheStepSizeAdvice) {
  SafetyMonitor monitor(SafetyLimits{});
  monitor.SetStartPosition(0.050);
  monitor.CheckCommand(0.051, 0, 0);  // the first command is fine: from now on, step sizes
  const SafetyStop stop = CatchStop([&] { monitor.CheckCommand(0.070, 1, 0); });
  EXPECT_THAT(stop.what(), HasSubstr("reduce the time step"));
  EXPECT_THAT(stop.what(), ::testing::Not(HasSubstr("first command")));
}

TEST(SafetyMonitor, ForceSoftUsesInitialStiffnessBeforeTwoSamples) {
  SafetyLimits limits;
  limits.max_increment = 1.0;  // isolate the force check
  limits.force_soft = 100.0;
  limits.force_hard = 200.0;
  SafetyMonitor monitor(limits);
  monitor.SetStartPosition(0.0);
  monitor.SetInitialStiffness(5000.0);
  monitor.CheckCommand(0.01, 0, 0);
  monitor.CheckMeasurement(0.01, 0.01, 50.0, 0, 0);
  // 50 N + 5000 N/m * 0.011 m = 105 N > 100 N.
  EXPECT_NEAR(monitor.PredictForce(0.021), 105.0, 1e-9);
  auto stop = CatchStop([&] { monitor.CheckCommand(0.021, 1, 0); });
  EXPECT_EQ(stop.limit(), "force_soft");
  EXPECT_NEAR(stop.value(), 105.0, 1e-9);
  EXPECT_NO_THROW(monitor.CheckCommand(0.019, 1, 0));  // 95 N
}

TEST(SafetyMonitor, ForceSoftSwitchesToSecantStiffness) {
  SafetyLimits limits;
  limits.max_increment = 1.0;
  limits.force_soft = 100.0;
  limits.force_hard = 200.0;
  SafetyMonitor monitor(limits);
  monitor.SetInitialStiffness(1000.0);  // a poor guess: the specimen is 10x stiffer
  monitor.CheckCommand(0.001, 0, 0);
  monitor.CheckMeasurement(0.001, 0.001, 10.0, 0, 0);
  monitor.CheckCommand(0.002, 1, 0);
  monitor.CheckMeasurement(0.002, 0.002, 20.0, 1, 0);  // secant 10,000 N/m
  EXPECT_NEAR(monitor.PredictForce(0.0115), 115.0, 1e-9);
  EXPECT_EQ(CatchStop([&] { monitor.CheckCommand(0.0115, 2, 0); }).limit(), "force_soft");
}

// A paced loop (1024 Hz) on the storey's specimen (1.19e6 N/m), 10 mm at 2 Hz, commands
// leading the measured position by a 22 ms plant delay, the load cell scattering ±200 N.
// Near a reversal two consecutive measurements are ~1 µm apart, so their secant is the
// scatter over a micrometre (up to ~4e8 N/m) and forecast 44 kN for a healthy command; the
// least-squares line through the window stays near the specimen's stiffness (~12 kN).
TEST(SafetyMonitor, StiffnessEstimateIgnoresPerTickScatter) {
  SafetyLimits limits;
  limits.max_increment = 0.002;
  limits.force_soft = 20e3;
  limits.force_hard = 50e3;
  SafetyMonitor monitor(limits);
  const double k = 1.19e6, amplitude = 0.01, omega = 2 * M_PI * 2, dt = 1.0 / 1024,
               delay = 0.022;
  monitor.SetInitialStiffness(k);
  monitor.SetStartPosition(amplitude * std::sin(omega * delay));
  unsigned long seed = 12345;
  double worst = 0;
  for (long i = 0; i < 2048; ++i) {
    const double t = (double(i) + 1) * dt;
    const double command = amplitude * std::sin(omega * (t + delay));
    worst = std::max(worst, std::abs(monitor.PredictForce(command)));
    ASSERT_NO_THROW(monitor.CheckCommand(command, i, 0)) << "tick " << i;
    seed = (seed * 1103515245 + 12345) % (1ul << 31);
    const double scatter = 200.0 * (2.0 * double(seed) / double(1ul << 31) - 1.0);
    const double x = amplitude * std::sin(omega * t);
    monitor.CheckMeasurement(command, x, k * x + scatter, i, 0);
  }
  EXPECT_LT(worst, 13e3);
}

TEST(SafetyMonitor, NonFiniteCommandsAreRefused) {
  SafetyMonitor monitor = MakeMonitor();
  for (double bad : {kNaN, kInf, -kInf}) {
    EXPECT_EQ(CatchStop([&] { monitor.CheckCommand(bad, 3, 0); }).limit(), "command_finite");
  }
  EXPECT_DOUBLE_EQ(monitor.last_safe_command(), 0.0);
}

TEST(SafetyMonitor, NonFiniteMeasurementsStop) {
  SafetyMonitor monitor = MakeMonitor();
  monitor.CheckCommand(0.001, 0, 0);
  EXPECT_EQ(CatchStop([&] { monitor.CheckMeasurement(0.001, 0.001, kNaN, 0, 0); }).limit(),
            "force_finite");
  EXPECT_EQ(CatchStop([&] { monitor.CheckMeasurement(0.001, 0.001, -kInf, 0, 0); }).limit(),
            "force_finite");
  EXPECT_EQ(CatchStop([&] { monitor.CheckMeasurement(0.001, kNaN, 1.0, 0, 0); }).limit(),
            "position_finite");
}

TEST(SafetyMonitor, ForceHardStopsAndReportsTheMeasurement) {
  SafetyMonitor monitor = MakeMonitor();
  monitor.CheckCommand(0.001, 4, 1);
  auto stop = CatchStop([&] { monitor.CheckMeasurement(0.001, 0.001, -10001.0, 4, 1); });
  EXPECT_EQ(stop.limit(), "force_hard");
  EXPECT_DOUBLE_EQ(stop.value(), 10001.0);
  EXPECT_DOUBLE_EQ(stop.limit_value(), 10e3);
  ASSERT_FALSE(stop.history().empty());
  EXPECT_TRUE(stop.history().back().answered);
  EXPECT_DOUBLE_EQ(stop.history().back().force, -10001.0);
  EXPECT_NO_THROW(monitor.CheckMeasurement(0.001, 0.001, 10000.0, 4, 1));  // at the limit: ok
}

TEST(SafetyMonitor, HistoryHoldsLastExchangesOldestFirst) {
  SafetyMonitor monitor(SafetyLimits{}, 4);
  monitor.SetInitialStiffness(1000.0);
  for (long step = 0; step < 10; ++step) {
    const double x = 1e-4 * static_cast<double>(step);
    monitor.CheckCommand(x, step, 0);
    monitor.CheckMeasurement(x, x, 1000.0 * x, step, 0);
  }
  monitor.CheckCommand(0.0011, 10, 1);  // sent, not answered
  const auto history = monitor.history();
  ASSERT_EQ(history.size(), 4u);
  EXPECT_EQ(history[0].step, 7);
  EXPECT_EQ(history[2].step, 9);
  EXPECT_TRUE(history[2].answered);
  EXPECT_DOUBLE_EQ(history[2].force, 0.9);
  EXPECT_EQ(history[3].step, 10);
  EXPECT_EQ(history[3].stage, 1);
  EXPECT_FALSE(history[3].answered);
  auto stop = CatchStop([&] { monitor.CheckCommand(kNaN, 10, 2); });
  EXPECT_EQ(stop.history().size(), 4u);
  EXPECT_EQ(stop.history().front().step, 7);
}

TEST(SafetyMonitor, InconsistentLimitsAreConfigErrors) {
  auto with = [](auto edit) {
    SafetyLimits limits;
    edit(limits);
    return limits;
  };
  EXPECT_THROW(SafetyMonitor(with([](SafetyLimits& l) { l.stroke_min = 0.2; })), ConfigError);
  EXPECT_THROW(SafetyMonitor(with([](SafetyLimits& l) { l.max_increment = 0; })), ConfigError);
  EXPECT_THROW(SafetyMonitor(with([](SafetyLimits& l) { l.force_soft = 2e4; })), ConfigError);
  EXPECT_THROW(SafetyMonitor(with([](SafetyLimits& l) { l.timeout = -1; })), ConfigError);
  EXPECT_THROW(SafetyMonitor(with([](SafetyLimits& l) { l.stroke_max = kNaN; })), ConfigError);
  SafetyMonitor monitor(SafetyLimits{});
  EXPECT_THROW(monitor.SetStartPosition(0.3), ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
