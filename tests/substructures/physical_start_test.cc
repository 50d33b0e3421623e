// PhysicalSubstructure::CheckStart (the start check of a new run): the actuator's position is
// read before anything moves and compared with the run's first command; farther than
// max_increment refuses (SafetyStop "start_position", nothing sent) unless `start: ramp`,
// which walks there in moves within max_increment through the gate.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
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

std::unique_ptr<PhysicalSubstructure> MakeIdealSlot() {
  SetupTransform setup;
  setup.p0 = 0.020;  // [m], the bench's p0_mm
  return std::make_unique<PhysicalSubstructure>(
      "r1", transfer::MakeEmulatedBench(transfer::LoadEmulatedBenchConfig(kIdeal)), setup,
      kLimits);
}

// An activated slot whose emulated bench was left at p0 + d [m] by an earlier run (its
// state restored from a slot that moved there in steps of at most 3 mm).
std::unique_ptr<PhysicalSubstructure> SlotLeftAt(double d) {
  auto earlier = MakeIdealSlot();
  earlier->Activate();
  const int n = static_cast<int>(std::ceil(std::abs(d) / 0.003));
  for (int k = 1; k <= n; ++k) TrialOne(*earlier, d * k / n, {k, 0, 0.001 * k});
  const nlohmann::json bench = earlier->transfer().SaveState();
  auto slot = MakeIdealSlot();
  slot->Activate();
  slot->transfer().RestoreState(bench);
  return slot;
}

TEST(PhysicalStart, RefusesBeforeMovingWhenTheActuatorIsFartherThanMaxIncrement) {
  auto slot = SlotLeftAt(0.0112);  // 31.2 mm, as an earlier run of rotor/ads.yaml left it
  const std::vector<double> d0{0.0};
  const long received = *slot->transfer().commands_received();
  try {
    slot->CheckStart({"r1", d0, false, {}});
    FAIL() << "no refusal";
  } catch (const transfer::SafetyStop& e) {
    EXPECT_EQ(e.limit(), "start_position");
    EXPECT_NEAR(e.value(), 0.0112, 1e-9);
    EXPECT_DOUBLE_EQ(e.limit_value(), 0.005);
    const std::string what = e.what();
    EXPECT_NE(what.find("0.0312 m (31.2 mm)"), std::string::npos) << what;
    EXPECT_NE(what.find("p0 = 0.02 m (20 mm)"), std::string::npos) << what;
    EXPECT_NE(what.find("start: ramp"), std::string::npos) << what;
    EXPECT_NE(what.find("move the actuator"), std::string::npos) << what;
  }
  EXPECT_EQ(*slot->transfer().commands_received(), received);  // nothing was sent
  EXPECT_EQ(slot->evaluations(), 0);
}

TEST(PhysicalStart, RampsWithinMaxIncrementWhenAsked) {
  auto slot = SlotLeftAt(0.0112);
  const std::vector<double> d0{0.0};
  std::vector<double> commands;
  const nlohmann::json record =
      slot->CheckStart({"r1", d0, true, [&] { commands.push_back(slot->actuator_exchange(0).command); }});
  EXPECT_EQ(record["read"], true);
  EXPECT_EQ(record["ramp"], true);
  EXPECT_EQ(record["ramp_moves"], 3);  // 11.2 mm in moves under 5 mm
  EXPECT_NEAR(record["actuators"][0]["read_position_m"].get<double>(), 0.0312, 1e-9);
  EXPECT_NEAR(record["actuators"][0]["first_command_m"].get<double>(), 0.020, 1e-12);
  ASSERT_EQ(commands.size(), 3u);
  double from = 0.0312;
  for (double c : commands) {
    EXPECT_LT(std::abs(c - from), 0.005);
    from = c;
  }
  EXPECT_NEAR(commands.back(), 0.020, 1e-12);
  EXPECT_NEAR(slot->actuator_exchange(0).position, 0.020, 1e-9);
}

TEST(PhysicalStart, StartsFromTheReadPositionWithinMaxIncrement) {
  auto slot = SlotLeftAt(0.003);  // 23 mm: within 5 mm of the first command (20 mm + d0)
  const std::vector<double> d0{0.001};
  const nlohmann::json record = slot->CheckStart({"r1", d0, false, {}});
  EXPECT_EQ(record["read"], true);
  EXPECT_EQ(record["ramp_moves"], 0);
  EXPECT_NEAR(record["actuators"][0]["first_command_m"].get<double>(), 0.021, 1e-12);
  EXPECT_NEAR(record["actuators"][0]["gap_m"].get<double>(), 0.002, 1e-9);
  EXPECT_EQ(slot->evaluations(), 0);
  // The gate now checks the first move from the read 23 mm: a command 6 mm away is refused.
  EXPECT_THROW(TrialOne(*slot, -0.003, {1, 0, 0.001}), transfer::SafetyStop);
}

}  // namespace
}  // namespace hybridtest::substructures
