// The two-actuator example with a yielding specimen (examples/06_blade_two_actuators,
// bouc-wen.yaml on bench-2act-bouc-wen.yaml): against its numerical twin (dummy-bouc-wen.yaml),
// and the safety of a specimen with several actuators: per-actuator lists and one hold for all.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <fstream>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/substructures/law_block.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
const std::string kExample = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

class StateRecorder final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

std::vector<std::vector<double>> RunSpecInMemory(io::RunSpec spec) {
  spec.output.files = false;
  spec.quiet = true;
  Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  return recorder.rows;
}

double WorstDeflection(const std::vector<std::vector<double>>& a,
                       const std::vector<std::vector<double>>& b, double* peak = nullptr) {
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    for (std::size_t j = 0; j < 2; ++j) {
      worst = std::max(worst, std::abs(a[i][j] - b[i][j]));
      if (peak) *peak = std::max(*peak, std::abs(b[i][j]));
    }
  }
  return worst;
}

// The bench deforms the specimen through every stage's trial (a physical specimen cannot be
// trialled and rolled back); the twin trials from the committed state and commits per step.
// Both integrate the same law: they agree to a small fraction of the deflection, and a twin
// that ignores the yielding (the virgin tangent Tᵀ K0 T) is far off.
TEST(MultiActuatorBoucWen, EmulatedSpecimenFollowsItsNumericalTwin) {
  const auto physical = RunSpecInMemory(io::LoadRunSpec(kExample + "bouc-wen.yaml"));
  io::RunSpec twin_spec = io::LoadRunSpec(kExample + "dummy-bouc-wen.yaml");
  ASSERT_TRUE(twin_spec.substructures.at(0).block_law);
  const auto twin = RunSpecInMemory(twin_spec);
  ASSERT_EQ(physical.size(), 10001u);
  double peak = 0.0;
  const double worst = WorstDeflection(physical, twin, &peak);
  std::cout << "[ bench against twin: " << worst << " m of a peak deflection " << peak << " m ]\n";
  EXPECT_LT(worst, 0.002 * peak) << "peak " << peak;
  // The elastic twin (the law's virgin tangent seen by the slots).
  substructures::LawBlock block(twin_spec.substructures[0].block_law->Clone(),
                                *twin_spec.substructures[0].block_transform);
  twin_spec.substructures[0].stiffness = *block.initial_stiffness();
  twin_spec.substructures[0].block_law.reset();
  const auto elastic = RunSpecInMemory(twin_spec);
  std::cout << "[ bench against the elastic twin: " << WorstDeflection(physical, elastic) << " m ]\n";
  EXPECT_GT(WorstDeflection(physical, elastic), 10.0 * worst);
  EXPECT_GT(WorstDeflection(physical, elastic), 0.05 * peak);  // the specimen yields
}

// A config that is the example with `safety:` replaced.
io::RunSpec WithSafety(const std::string& safety, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest-multi-safety-{}", ::getpid());
  fs::create_directories(dir);
  std::string text = test_support::ReadText(kExample + "emulated.yaml");
  text = text.substr(0, text.find("    safety:")) + "    safety: " + safety + "\noutput:\n  csv: x.csv\n";
  text.replace(text.find("file: blade_tip.yaml"), 20, "file: " + kExample + "blade_tip.yaml");
  text.replace(text.find("config: bench-2act.yaml"), 23, "config: " + kExample + "bench-2act.yaml");
  const fs::path path = dir / (name + ".yaml");
  std::ofstream(path) << text;
  return io::LoadRunSpec(path.string());
}

TEST(MultiActuatorSafety, EveryKeyTakesOneValuePerActuator) {
  const io::RunSpec spec = WithSafety(
      "{stroke_min: [-0.10, -0.05], stroke_max: [0.10, 0.06], max_increment: [0.002, 0.003], "
      "force_soft: [2000, 1500], force_hard: [3000, 2500], timeout: [5, 7]}", "lists");
  const auto& limits = spec.substructures.at(0).physical->actuator_limits;
  ASSERT_EQ(limits.size(), 2u);
  EXPECT_EQ(limits[1].stroke_min, -0.05);
  EXPECT_EQ(limits[1].stroke_max, 0.06);
  EXPECT_EQ(limits[1].max_increment, 0.003);
  EXPECT_EQ(limits[1].force_soft, 1500.0);
  EXPECT_EQ(limits[1].force_hard, 2500.0);
  EXPECT_EQ(limits[1].timeout, 7.0);
  EXPECT_EQ(limits[0].force_hard, 3000.0);
  // The transfer system waits as long as the slowest actuator may take.
  EXPECT_EQ(spec.substructures[0].physical->limits.timeout, 7.0);
}

TEST(MultiActuatorSafety, AListOfTheWrongLengthNamesTheKeyAndTheLength) {
  for (const char* key : {"stroke_min", "stroke_max", "max_increment", "force_soft",
                          "force_hard", "timeout"}) {
    try {
      WithSafety(fmt::format("{{{}: [1, 2, 3]}}", key), key);
      ADD_FAILURE() << key << ": a list of 3 for 2 actuators was accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(fmt::format("safety.{}", key)), std::string::npos) << what;
      EXPECT_NE(what.find("expected 2"), std::string::npos) << what;
    }
  }
}

// One actuator's refused command holds the whole specimen: nothing moves, and the bench
// refuses every further command until it is activated again.
TEST(MultiActuatorSafety, AHoldHoldsEveryActuator) {
  const auto bench = transfer::LoadEmulatedBenchSpec(kExample + "bench-2act.yaml");
  substructures::LinearSetup setup;
  setup.p0 = Eigen::Vector2d(0.02, 0.03);
  setup.transform = Eigen::Matrix2d::Identity();
  setup.load_cell_zero = Eigen::Vector2d::Zero();
  transfer::SafetyLimits wide, narrow;
  wide.max_increment = 0.01;
  narrow.max_increment = 0.01;
  narrow.stroke_max = 0.032;  // actuator 2 may go 2 mm past its p0
  substructures::PhysicalSubstructure sub(
      "blade1", std::make_unique<transfer::EmulatedBench>(bench), setup, {wide, narrow});
  sub.Activate();
  auto& emulated = dynamic_cast<transfer::EmulatedBench&>(sub.transfer());
  std::vector<double> r(2);
  sub.Trial(std::vector<double>{0.001, 0.001}, r, {0, 0, 0.0});
  EXPECT_THROW(sub.Trial(std::vector<double>{0.002, 0.003}, r, {1, 0, 0.001}),
               transfer::SafetyStop);
  EXPECT_NEAR(emulated.actuator_position(0), 0.021, 1e-12);  // actuator 1 did not move either
  EXPECT_NEAR(emulated.actuator_position(1), 0.031, 1e-12);
  const std::vector<double> commands{21.0, 31.0};  // [mm], where they are
  std::vector<transfer::Measurement> out(2);
  EXPECT_THROW(emulated.Execute(commands, out), TransferError);  // held: every actuator
  EXPECT_EQ(*emulated.commands_received(), 1);
}

}  // namespace
}  // namespace hybridtest::runner
