// PhysicalSubstructure::SaveState/RestoreState and ReimposeCommitted (resume): the last
// committed command is re-imposed once (ramped in moves within max_increment if the bench is
// elsewhere), the force is compared with the committed one, and a mismatch refuses with a
// SafetyStop naming both forces.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "substructures/trial_one.h"

namespace hybridtest::substructures {
namespace {

using testing::TrialOne;

const std::string kIdeal = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/bench-ideal.yaml";
const transfer::SafetyLimits kLimits{-0.15, 0.15, 0.005, 8000.0, 10000.0, 5.0};

std::unique_ptr<PhysicalSubstructure> MakeIdealSlot(std::optional<double> k0 = std::nullopt) {
  SetupTransform setup;
  setup.p0 = 0.020;  // [m], the bench's p0_mm
  return std::make_unique<PhysicalSubstructure>(
      "r1", transfer::MakeEmulatedBench(transfer::LoadEmulatedBenchConfig(kIdeal)), setup, kLimits,
      k0);
}

// A slot that has made a few trials up to d = 4 × increment (12 mm), and its saved state.
nlohmann::json StateAfterTrials(double increment = 0.003) {
  auto slot = MakeIdealSlot();
  slot->Activate();
  for (int k = 1; k <= 4; ++k) TrialOne(*slot, increment * k, {k, 0, 0.001 * k});
  slot->Commit();
  return nlohmann::json::parse(slot->SaveState().dump());
}

// The SafetyStop with which a slot restored from `state` refuses to resume.
transfer::SafetyStop RefusalOf(const nlohmann::json& state) {
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->RestoreState(state);
  try {
    slot->ReimposeCommitted(0.0, 0.0, 4, {});
  } catch (const transfer::SafetyStop& e) {
    return e;
  }
  ADD_FAILURE() << "no SafetyStop";
  return transfer::SafetyStop("none", 0.0, 0.0, 0, 0, {}, "");
}

TEST(PhysicalResume, ReimposesTheCommittedCommandOnce) {
  const auto state = StateAfterTrials();
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->RestoreState(state);  // the in-process bench comes back where it was
  std::vector<bool> moves;
  const auto check = slot->ReimposeCommitted(0.0, 0.0, 4, [&](bool r) { moves.push_back(r); });
  EXPECT_EQ(moves, std::vector<bool>{true});
  EXPECT_NEAR(check.actuators[0].command, 0.032, 1e-12);
  ASSERT_TRUE(check.actuators[0].read_position.has_value());
  EXPECT_NEAR(*check.actuators[0].read_position, 0.032, 1e-12);
  EXPECT_EQ(check.ramp_moves, 0);
  // Ideal bench: exactly; the tolerance is 1 % of force_hard.
  EXPECT_EQ(check.actuators[0].force, check.actuators[0].committed_force);
  EXPECT_DOUBLE_EQ(check.actuators[0].force_tolerance, 100.0);
}

TEST(PhysicalResume, RampsBackWithinTheIncrementLimit) {
  auto state = StateAfterTrials();
  state["transfer"] = nullptr;  // the bench is NOT restored: it starts at p0 = 20 mm
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->RestoreState(state);
  std::vector<double> commands;
  const auto check = slot->ReimposeCommitted(
      0.0, 0.0, 4, [&](bool) { commands.push_back(slot->actuator_exchange(0).command); });
  EXPECT_NEAR(*check.actuators[0].read_position, 0.020, 1e-12);
  EXPECT_EQ(check.ramp_moves, 2);  // 12 mm in moves of at most 5 mm: 3 moves
  ASSERT_EQ(commands.size(), 3u);
  double previous = 0.020;
  for (double c : commands) {
    EXPECT_LE(std::abs(c - previous), kLimits.max_increment + 1e-15);
    previous = c;
  }
  EXPECT_NEAR(commands.back(), 0.032, 1e-12);
  EXPECT_NEAR(check.actuators[0].force, check.actuators[0].committed_force, 1e-9);
}

TEST(PhysicalResume, RefusesAForceThatDisagreesWithTheJournal) {
  auto state = StateAfterTrials();
  const double committed = state["last"][0][2].get<double>();  // [command, position, force, t]
  state["last"][0][2] = committed + 150.0;  // the specimen changed (say, it cracked)
  {
    const transfer::SafetyStop e = RefusalOf(state);
    EXPECT_EQ(e.limit(), "resume_force_tolerance");
    EXPECT_NEAR(e.value(), 150.0, 1e-9);
    EXPECT_DOUBLE_EQ(e.limit_value(), 100.0);
    const std::string what = e.what();
    EXPECT_NE(what.find(fmt::format("{} N", committed + 150.0)), std::string::npos) << what;
    EXPECT_NE(what.find("--force-tolerance"), std::string::npos) << what;
  }
  // A wider tolerance accepts it.
  auto again = MakeIdealSlot();
  again->Activate();
  again->RestoreState(state);
  EXPECT_NO_THROW(again->ReimposeCommitted(200.0, 0.0, 4, {}));
}

TEST(PhysicalResume, AGapOfExactlyTwoIncrementsIsRampedStrictlyWithinTheLimit) {
  auto state = StateAfterTrials(0.0025);  // committed command 30 mm; the bench starts at 20 mm
  state["transfer"] = nullptr;
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->RestoreState(state);
  std::vector<double> commands;
  const auto check = slot->ReimposeCommitted(
      0.0, 0.0, 4, [&](bool) { commands.push_back(slot->actuator_exchange(0).command); });
  EXPECT_EQ(check.ramp_moves, 2);  // 10 mm = 2 × 5 mm: three moves, none at the limit
  double previous = 0.020;
  for (double c : commands) {
    EXPECT_LT(std::abs(c - previous), kLimits.max_increment);
    previous = c;
  }
  EXPECT_NEAR(commands.back(), 0.030, 1e-12);
}

TEST(PhysicalResume, RefusesAPositionThatDisagreesWithTheJournal) {
  auto state = StateAfterTrials();
  // The journal says the actuator stood 2 mm elsewhere (a slipped clamp, a re-zeroed encoder):
  // the force alone would not tell on a soft specimen.
  state["last"][0][1] = state["last"][0][1].get<double>() + 0.002;
  {
    const transfer::SafetyStop e = RefusalOf(state);
    EXPECT_EQ(e.limit(), "resume_position_tolerance");
    EXPECT_NEAR(e.value(), 0.002, 1e-12);
    EXPECT_DOUBLE_EQ(e.limit_value(), 0.25 * kLimits.max_increment);
    EXPECT_NE(std::string(e.what()).find("--position-tolerance"), std::string::npos);
  }
  auto again = MakeIdealSlot();
  again->Activate();
  again->RestoreState(state);
  EXPECT_NO_THROW(again->ReimposeCommitted(0.0, 0.003, 4, {}));
}

// The state of a one-actuator run saved before the one- and several-actuator substructures were
// one class: {"last": {"command_m", ...}, "k0": number or null, "safety": one monitor state}.
nlohmann::json OneActuatorStateOfBefore(const nlohmann::json& state) {
  const auto& last = state["last"][0];
  return {{"last", {{"command_m", last[0]}, {"position_m", last[1]}, {"force_N", last[2]},
                    {"lab_time_s", last[3]}}},
          {"evaluations", state["evaluations"]},
          {"k0", 7200.0},
          {"safety", state["safety"][0]},
          {"transfer", state["transfer"]}};
}

TEST(PhysicalResume, AOneActuatorStateSavedBeforeStillResumes) {
  const auto state = StateAfterTrials();
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->RestoreState(OneActuatorStateOfBefore(state));
  EXPECT_EQ(slot->evaluations(), state["evaluations"].get<long>());
  ASSERT_TRUE(slot->initial_stiffness());
  EXPECT_EQ((*slot->initial_stiffness())(0, 0), 7200.0);
  const auto check = slot->ReimposeCommitted(0.0, 0.0, 4, {});
  EXPECT_NEAR(check.actuators[0].command, 0.032, 1e-12);
  EXPECT_EQ(check.ramp_moves, 0);
  EXPECT_EQ(check.actuators[0].force, check.actuators[0].committed_force);
  // What it saves now reads back the same.
  auto again = MakeIdealSlot();
  again->Activate();
  again->RestoreState(nlohmann::json::parse(slot->SaveState().dump()));
  EXPECT_EQ(again->SaveState(), slot->SaveState());
}

TEST(PhysicalResume, TheDefaultForceToleranceFollowsK0AndThePositionTolerance) {
  auto slot = MakeIdealSlot(7200.0);  // [N/m], the paper's blade
  // 1 % of 10 kN is 100 N, which is 13.9 mm on this specimen; K0 × 1.25 mm is 9 N.
  EXPECT_DOUBLE_EQ(slot->DefaultResumePositionTolerance(), 0.00125);
  EXPECT_DOUBLE_EQ(slot->DefaultResumeForceTolerance(0.00125), 9.0);
  EXPECT_DOUBLE_EQ(MakeIdealSlot()->DefaultResumeForceTolerance(0.00125), 100.0);
}

}  // namespace
}  // namespace hybridtest::substructures
