// PhysicalSubstructure: the safety rule "a command beyond a limit is never executed", Hold()
// on every failure, unit conversion at the seam, evaluation counting; over a recording fake,
// over a NumericalLoopback and over an EmulatedBench.
#include "hybridtest/substructures/physical_substructure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>

#include "hybridtest/constitutive/linear_spring.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/numerical_loopback.h"
#include "substructures/recording_transfer.h"
#include "substructures/trial_one.h"

namespace hybridtest::substructures {
namespace {

using testing::TrialOne;

using testing::RecordingTransfer;
using testing::TransferLog;

constexpr double kStiffness = 7200.0;  // [N/m]
constexpr double kP0 = 0.020;          // [m]
const transfer::BenchUnits kMmKn{1e-3, 1e3, "mm", "kN"};

SetupTransform SetupP0() {
  SetupTransform s;
  s.p0 = kP0;
  return s;
}

// A PhysicalSubstructure over a recording spring bench speaking mm and kN.
struct Rig {
  explicit Rig(transfer::SafetyLimits limits = {})
      : log(std::make_shared<TransferLog>()),
        sub("r1",
            std::make_unique<RecordingTransfer>(log, kMmKn, kStiffness * 1e-3 / 1e3, kP0 * 1e3),
            SetupP0(), limits) {
    sub.Activate();
  }
  std::shared_ptr<TransferLog> log;
  PhysicalSubstructure sub;
};

template <class E>
E ExpectThrows(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception: " << e.what();
    throw;
  }
  ADD_FAILURE() << "no exception";
  throw std::logic_error("no exception");
}

TEST(PhysicalSubstructure, ConvertsToBenchUnitsAndBackToSi) {
  Rig rig;
  EXPECT_EQ(rig.log->activations, 1);
  const double r = TrialOne(rig.sub, 0.004, {0, 0, 0.0});
  ASSERT_EQ(rig.log->executed.size(), 1u);
  EXPECT_NEAR(rig.log->executed[0], 24.0, 1e-12);  // p0 + d in mm
  EXPECT_NEAR(r, kStiffness * 0.004, 1e-9);        // N, from kN
  const Exchange e = rig.sub.actuator_exchange(0);
  EXPECT_NEAR(e.command, 0.024, 1e-15);
  EXPECT_NEAR(e.position, 0.024, 1e-15);
  EXPECT_NEAR(e.force, kStiffness * 0.004, 1e-9);
  EXPECT_EQ(e.lab_time, 1.5);
  EXPECT_EQ(rig.sub.evaluations(), 1);
  EXPECT_TRUE(rig.sub.is_physical());
  rig.sub.Commit();  // a no-op for steel: the move already happened
  EXPECT_EQ(rig.log->executed.size(), 1u);
  EXPECT_EQ(rig.log->holds, 0);
}

TEST(PhysicalSubstructure, CountsEveryEvaluation) {
  Rig rig;
  for (int i = 0; i < 7; ++i) TrialOne(rig.sub, 1e-4 * i, {i / 2, i % 2, 1e-3 * i});
  EXPECT_EQ(rig.sub.evaluations(), 7);
  EXPECT_EQ(rig.log->executed.size(), 7u);
}

TEST(PhysicalSubstructure, CommandBeyondStrokeIsNeverExecutedAndHolds) {
  transfer::SafetyLimits limits;
  limits.stroke_max = 0.030;
  Rig rig(limits);
  TrialOne(rig.sub, 0.004, {0, 0, 0.0});   // 24 mm
  TrialOne(rig.sub, 0.0075, {0, 1, 0.0});  // 27.5 mm
  const auto stop = ExpectThrows<transfer::SafetyStop>([&] { TrialOne(rig.sub, 0.011, {1, 0, 0.001}); });
  EXPECT_EQ(stop.limit(), "stroke_max");
  EXPECT_NEAR(stop.value(), 0.031, 1e-15);
  EXPECT_EQ(stop.step(), 1);
  EXPECT_EQ(stop.stage(), 0);
  EXPECT_EQ(rig.log->executed.size(), 2u) << "the refused command reached the bench";
  EXPECT_LE(rig.log->executed.back(), 30.0);
  EXPECT_EQ(rig.log->holds, 1);
  EXPECT_EQ(rig.sub.evaluations(), 2);
}

TEST(PhysicalSubstructure, IncrementBeyondLimitIsNeverExecuted) {
  Rig rig;  // max_increment 5 mm
  TrialOne(rig.sub, 0.0, {0, 0, 0.0});
  const auto stop = ExpectThrows<transfer::SafetyStop>([&] { TrialOne(rig.sub, 0.006, {0, 1, 0.0}); });
  EXPECT_EQ(stop.limit(), "max_increment");
  EXPECT_EQ(rig.log->executed.size(), 1u);
  EXPECT_EQ(rig.log->holds, 1);
}

TEST(PhysicalSubstructure, PredictedForceBeyondSoftLimitIsNeverExecuted) {
  transfer::SafetyLimits limits;
  limits.force_soft = 50.0;
  limits.force_hard = 60.0;
  Rig rig(limits);
  TrialOne(rig.sub, 0.001, {0, 0, 0.0});  // 7.2 N
  TrialOne(rig.sub, 0.002, {0, 1, 0.0});  // 14.4 N: the secant stiffness is now 7200 N/m
  TrialOne(rig.sub, 0.004, {1, 0, 0.0});  // 28.8 N
  const auto stop = ExpectThrows<transfer::SafetyStop>([&] { TrialOne(rig.sub, 0.0075, {1, 1, 0.0}); });
  EXPECT_EQ(stop.limit(), "force_soft");
  EXPECT_NEAR(stop.value(), 54.0, 1e-6);
  EXPECT_EQ(rig.log->executed.size(), 3u);
  EXPECT_EQ(rig.log->holds, 1);
}

TEST(PhysicalSubstructure, MeasuredForceBeyondHardLimitStopsAndHolds) {
  transfer::SafetyLimits limits;
  limits.force_soft = 40.0;
  limits.force_hard = 50.0;
  limits.max_increment = 0.02;  // the first command starts from p0 = 0: allow the 10 mm move
  Rig rig(limits);
  // No measurement yet: nothing to predict from, so the command goes out; the measurement
  // (72 N) is then caught.
  const auto stop = ExpectThrows<transfer::SafetyStop>([&] { TrialOne(rig.sub, 0.010, {0, 0, 0.0}); });
  EXPECT_EQ(stop.limit(), "force_hard");
  EXPECT_NEAR(stop.value(), 72.0, 1e-9);
  EXPECT_EQ(rig.log->executed.size(), 1u);
  EXPECT_EQ(rig.log->holds, 1);
  EXPECT_EQ(rig.sub.evaluations(), 1);
  ASSERT_FALSE(stop.history().empty());
  EXPECT_TRUE(stop.history().back().answered);
  EXPECT_NEAR(stop.history().back().force, 72.0, 1e-9);
}

TEST(PhysicalSubstructure, NonFiniteMeasurementStopsAndHolds) {
  Rig rig;
  rig.log->nan_force_at = 1;
  TrialOne(rig.sub, 0.001, {0, 0, 0.0});
  const auto stop = ExpectThrows<transfer::SafetyStop>([&] { TrialOne(rig.sub, 0.002, {0, 1, 0.0}); });
  EXPECT_EQ(stop.limit(), "force_finite");
  EXPECT_EQ(stop.step(), 0);
  EXPECT_EQ(stop.stage(), 1);
  EXPECT_EQ(rig.log->holds, 1);
  EXPECT_EQ(rig.sub.evaluations(), 2);
  EXPECT_TRUE(std::isnan(rig.sub.actuator_exchange(0).force));
}

TEST(PhysicalSubstructure, NonFiniteCommandIsNeverExecuted) {
  Rig rig;
  const auto stop = ExpectThrows<transfer::SafetyStop>(
      [&] { TrialOne(rig.sub, std::numeric_limits<double>::quiet_NaN(), {3, 1, 0.0}); });
  EXPECT_EQ(stop.limit(), "command_finite");
  EXPECT_TRUE(rig.log->executed.empty());
  EXPECT_EQ(rig.log->holds, 1);
}

TEST(PhysicalSubstructure, TransferErrorHoldsAndPropagates) {
  Rig rig;
  rig.log->throw_transfer_error_at = 2;
  TrialOne(rig.sub, 0.001, {0, 0, 0.0});
  TrialOne(rig.sub, 0.001, {0, 1, 0.0});
  EXPECT_THROW(TrialOne(rig.sub, 0.001, {1, 0, 0.0}), TransferError);
  EXPECT_EQ(rig.log->holds, 1);
  EXPECT_EQ(rig.sub.evaluations(), 2);  // the failed exchange returned nothing
}

TEST(PhysicalSubstructure, LifecycleIsForwardedAndDestructorHoldsAnActiveBench) {
  auto log = std::make_shared<TransferLog>();
  {
    PhysicalSubstructure sub("r1", std::make_unique<RecordingTransfer>(log, kMmKn, 1.0, 0.0),
                             SetupTransform{}, {});
    sub.Activate();
    EXPECT_EQ(log->activations, 1);
  }
  EXPECT_EQ(log->holds, 1) << "an active substructure destroyed without Deactivate must hold";
  {
    PhysicalSubstructure sub("r1", std::make_unique<RecordingTransfer>(log, kMmKn, 1.0, 0.0),
                             SetupTransform{}, {});
    sub.Activate();
    sub.Deactivate();
    EXPECT_EQ(log->deactivations, 1);
    sub.Deactivate();  // idempotent
    EXPECT_EQ(log->deactivations, 1);
  }
  EXPECT_EQ(log->holds, 1);
}

TEST(PhysicalSubstructure, RejectsAnInvalidSetupOrNoTransfer) {
  SetupTransform bad;
  bad.sign = 2.0;
  auto log = std::make_shared<TransferLog>();
  EXPECT_THROW(PhysicalSubstructure("r1", std::make_unique<RecordingTransfer>(log, kMmKn, 1, 0),
                                    bad, {}),
               ConfigError);
  EXPECT_THROW(PhysicalSubstructure("r1", nullptr, SetupTransform{}, {}), Error);
}

TEST(PhysicalSubstructure, OverNumericalLoopbackIsTheSpring) {
  PhysicalSubstructure sub(
      "r1",
      std::make_unique<transfer::NumericalLoopback>(
          std::make_unique<constitutive::LinearSpring>(kStiffness), kP0),
      SetupP0(), {});
  sub.Activate();
  for (double d : {0.0, 0.001, -0.002, 0.0025}) {
    EXPECT_NEAR(TrialOne(sub, d, {0, 0, 0.0}), kStiffness * d, 1e-9) << d;
  }
  EXPECT_EQ(sub.evaluations(), 4);
  // A refused command holds the loopback: it refuses to move until activated again.
  EXPECT_THROW(TrialOne(sub, 0.2, {1, 0, 0.0}), transfer::SafetyStop);
  EXPECT_THROW(TrialOne(sub, 0.003, {1, 0, 0.0}), TransferError);
  sub.Activate();
  EXPECT_NEAR(TrialOne(sub, 0.003, {1, 0, 0.0}), kStiffness * 0.003, 1e-9);
}

TEST(PhysicalSubstructure, OverEmulatedBenchRefusedCommandNeverMovesTheActuator) {
  auto config = transfer::LoadEmulatedBenchConfig(std::string(HYBRIDTEST_SOURCE_DIR) +
                                                  "/examples/rotor/bench-ideal.yaml");
  auto bench = transfer::MakeEmulatedBench(config);
  transfer::EmulatedBench* raw = bench.get();
  transfer::SafetyLimits limits;
  limits.stroke_max = 0.025;  // tighter than the bench's own 150 mm
  PhysicalSubstructure sub("r1", std::move(bench), SetupP0(), limits);
  sub.Activate();
  EXPECT_NEAR(TrialOne(sub, 0.001, {0, 0, 0.0}), kStiffness * 0.001, 1e-9);
  EXPECT_NEAR(TrialOne(sub, 0.004, {0, 1, 0.0}), kStiffness * 0.004, 1e-9);
  EXPECT_EQ(raw->command_count(), 2);
  const double position = raw->actuator_position();
  EXPECT_NEAR(position, 0.024, 1e-9);
  EXPECT_GT(sub.actuator_exchange(0).lab_time, 0.0);

  EXPECT_THROW(TrialOne(sub, 0.0055, {1, 0, 0.001}), transfer::SafetyStop);
  EXPECT_EQ(raw->command_count(), 2) << "the refused command reached the bench";
  EXPECT_TRUE(raw->holding());
  EXPECT_EQ(raw->actuator_position(), position) << "the actuator moved on a refused command";
  EXPECT_EQ(sub.evaluations(), 2);
}

TEST(PhysicalSubstructure, OverEmulatedBenchABenchRefusalHolds) {
  // The runner's limits are wide, the bench's own are tight: the bench refuses and holds.
  auto config = transfer::LoadEmulatedBenchConfig(std::string(HYBRIDTEST_SOURCE_DIR) +
                                                  "/examples/rotor/bench-ideal.yaml");
  config.safety.stroke_max = 0.022;
  auto bench = transfer::MakeEmulatedBench(config);
  transfer::EmulatedBench* raw = bench.get();
  PhysicalSubstructure sub("r1", std::move(bench), SetupP0(), {});
  sub.Activate();
  TrialOne(sub, 0.001, {0, 0, 0.0});
  const double position = raw->actuator_position();
  EXPECT_THROW(TrialOne(sub, 0.003, {0, 1, 0.0}), transfer::SafetyStop);
  EXPECT_TRUE(raw->holding());
  EXPECT_EQ(raw->actuator_position(), position);
}

}  // namespace
}  // namespace hybridtest::substructures
