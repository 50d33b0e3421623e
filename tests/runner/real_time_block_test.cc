// Real time with a specimen on two actuators that serves two slots (issue 32): the delay check
// gives a margin for each slot of the block; a lab-time bench of two actuators is refused before
// anything moves; on an ideal paced plant the run in virtual time equals its numerical twin
// r = Tᵀ K T d; on the wall clock every actuator is paced.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hybridtest/common/clock.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/delay_stability.h"
#include "hybridtest/runner/paced_loop.h"
#include "runner/plant_pair.h"

namespace hybridtest::runner {
namespace {

const std::string kExample =
    std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// examples/06_blade_two_actuators/<file> with α-OS, `duration` and (optionally) a real_time
// block.
io::RunSpec Spec(const std::string& file, double duration, bool real_time,
               const std::string& clock = "virtual") {
  std::ifstream in(kExample + file);
  std::stringstream text;
  text << in.rdbuf();
  std::string config = Replace(text.str(), "tableau: heun", "scheme: alpha-os");
  config = Replace(config, "duration: 10.0",
                   "duration: " + std::to_string(duration) +
                       (real_time ? "\nreal_time: {hold_after_misses: 0, lock_memory: false}"
                                  : ""));
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(
      YamlInput::FromText(config, kExample + "real-time-" + file)));
  spec.output.files = false;
  spec.quiet = true;
  if (real_time) spec.real_time.clock = clock;
  return spec;
}

// The actuator stiffnesses of the paced plants [N/m], T and p0 of emulated.yaml.
const std::vector<double> kActuatorK = {5000.0, 3000.0};
Eigen::MatrixXd Transform() { return (Eigen::MatrixXd(2, 2) << 1.0, 0.0, 0.6, 0.8).finished(); }
Eigen::MatrixXd TwinStiffness() {
  const Eigen::MatrixXd T = Transform();
  return T.transpose() * Eigen::Vector2d(kActuatorK[0], kActuatorK[1]).asDiagonal() * T;
}

// The example's specimen on two ideal paced plants instead of the lab-time bench.
io::RunSpec PlantSpec(double duration, int* paced, const std::string& clock = "virtual") {
  io::RunSpec spec = Spec("emulated.yaml", duration, true, clock);
  auto& physical = *spec.substructures.at(0).physical;
  physical.transfer = {"plant pair", [paced]() -> std::unique_ptr<transfer::TransferSystem> {
                         return std::make_unique<test::PlantPair>(kActuatorK,
                                                                  std::vector{0.02, 0.03}, paced);
                       }};
  physical.initial_stiffness_matrix = TwinStiffness();
  return spec;
}

class States final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kCommitted) {
      std::vector<double> row(e.x.begin(), e.x.end());
      row.insert(row.end(), e.r.begin(), e.r.end());
      rows.push_back(std::move(row));
    }
  }
  std::vector<std::vector<double>> rows;
};

TEST(RealTimeBlock, TheDelayCheckGivesAMarginForEachSlotOfTheBlock) {
  // One substructure serves both slots: the check once indexed substructures by slot (SIGSEGV).
  Session lab(Spec("emulated.yaml", 1.0, false));  // a lab-time bench: no real-time run
  const auto lab_margins = CheckDelayStability(lab);
  ASSERT_EQ(lab_margins.size(), 2u);
  EXPECT_EQ(lab_margins[0].slot, "r_flap");
  EXPECT_EQ(lab_margins[1].slot, "r_edge");
  EXPECT_EQ(lab_margins[0].substructure, "blade1");
  EXPECT_FALSE(lab_margins[0].known_plant);  // a lab-time bench does not know its delay

  int paced = 0;
  Session session(PlantSpec(1.0, &paced));
  const auto margins = CheckDelayStability(session);
  ASSERT_EQ(margins.size(), 2u);
  const Eigen::MatrixXd K = TwinStiffness();
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(margins[static_cast<std::size_t>(s)].k0, K(s, s));
    EXPECT_TRUE(margins[static_cast<std::size_t>(s)].known_plant);
    EXPECT_EQ(margins[static_cast<std::size_t>(s)].plant_delay, 0.0);  // ideal, no delay
    EXPECT_FALSE(margins[static_cast<std::size_t>(s)].unstable());
  }
  EXPECT_EQ(ToJson(margins).size(), 2u);
}

TEST(RealTimeBlock, ALabTimeBenchOfTwoActuatorsIsRefusedBeforeAnythingMoves) {
  // Refused as the session builds its pacer: nothing is activated or sent before that.
  try {
    Session session(Spec("emulated.yaml", 1.0, true));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("substructures.blade1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot run in real time"), std::string::npos);
  }
  EXPECT_THROW(Session(Spec("emulated.yaml", 1.0, true, "wall")), ConfigError);
}

TEST(RealTimeBlock, IdealPlantsInVirtualTimeEqualTheNumericalTwin) {
  int paced = 0;
  Session session(PlantSpec(2.0, &paced));
  States states;
  session.AddObserver(states);
  const StepResult r = session.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_EQ(paced, 2);  // both actuators
  EXPECT_EQ(session.paced_loop()->statistics().ticks, 2000);

  io::RunSpec twin = Spec("dummy.yaml", 2.0, false);
  twin.substructures.at(0).law.reset();
  twin.substructures.at(0).stiffness = TwinStiffness();
  Session numerical(std::move(twin));
  States expected;
  numerical.AddObserver(expected);
  ASSERT_EQ(numerical.Run().status, SessionStatus::kFinished);

  ASSERT_EQ(states.rows.size(), 2001u);
  ASSERT_EQ(states.rows.size(), expected.rows.size());
  double worst = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < states.rows.size(); ++i) {
    for (std::size_t j = 0; j < states.rows[i].size(); ++j) {
      worst = std::max(worst, std::abs(states.rows[i][j] - expected.rows[i][j]));
    }
    peak = std::max(peak, std::abs(expected.rows[i][0]));
  }
  EXPECT_LE(worst, 1e-9);
  EXPECT_GT(peak, 1e-4);  // the blade moved [m]
}

TEST(RealTimeBlock, TheWallClockPacesEveryActuator) {
  int paced = 0;
  Session session(PlantSpec(0.2, &paced, "wall"));
  const StepResult r = session.Run();
  const PacedLoop& loop = *session.paced_loop();
  EXPECT_EQ(loop.clock_name(), "wall");
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  EXPECT_EQ(paced, 2);
  EXPECT_EQ(loop.statistics().ticks, 200);
  // One command per actuator per tick, and the settled one at x_0.
  const auto* pair =
      dynamic_cast<const test::PlantPair*>(session.substructures()[0]->transfer_system());
  ASSERT_NE(pair, nullptr);
  EXPECT_EQ(pair->plant(0).commands_received().value_or(0), 201);
  EXPECT_EQ(pair->plant(1).commands_received().value_or(0), 201);
  RecordProperty("late_p99_us", std::to_string(1e6 * loop.statistics().late_p99));
}

}  // namespace
}  // namespace hybridtest::runner
