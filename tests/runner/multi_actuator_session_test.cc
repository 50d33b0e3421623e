// A specimen on two actuators that serves two slots (examples/06_blade_two_actuators): the
// contract against the numerical substructure Tᵀ K T, the journal's channels per actuator, the
// K0 ramp, and the gate that refuses a whole command vector.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/safety_gate.h"
#include "transfer/bench_fake.h"

namespace hybridtest::runner {
namespace {

const std::string kExample = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";

// Every committed row's [q; u].
class StateRecorder final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

std::vector<std::vector<double>> RunInMemory(const std::string& config) {
  io::RunSpec spec = io::LoadRunSpec(config);
  spec.output.files = false;
  spec.quiet = true;
  Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  return recorder.rows;
}

TEST(MultiActuatorSession, TwoActuatorBenchMatchesTheNumericalTransformedStiffness) {
  const auto physical = RunInMemory(kExample + "emulated.yaml");
  const auto numerical = RunInMemory(kExample + "dummy.yaml");
  ASSERT_EQ(physical.size(), 10001u);
  ASSERT_EQ(physical.size(), numerical.size());
  double worst = 0.0, peak_flap = 0.0, peak_edge = 0.0;
  for (std::size_t i = 0; i < physical.size(); ++i) {
    ASSERT_EQ(physical[i].size(), 4u);  // q_flap, q_edge, u1, u2
    for (std::size_t j = 0; j < 4; ++j) {
      worst = std::max(worst, std::abs(physical[i][j] - numerical[i][j]));
    }
    peak_flap = std::max(peak_flap, std::abs(numerical[i][0]));
    peak_edge = std::max(peak_edge, std::abs(numerical[i][1]));
  }
  EXPECT_LT(worst, 1e-9);
  // The test means something: both deflections move by millimetres.
  EXPECT_GT(peak_flap, 1e-3);
  EXPECT_GT(peak_edge, 1e-3);
}

TEST(MultiActuatorSession, TheSameOverTcpThroughTheBenchProtocol) {
  // `hybridtest bench` serving the two-actuator bench; the run's transfer is a BenchClient.
  const auto bench_config = transfer::LoadEmulatedBenchSpec(kExample + "bench-2act.yaml");
  transfer::EmulatedBench bench(bench_config);
  transfer::BenchServerOptions options;
  options.limits = bench_config.actuators[0].safety;
  for (const auto& a : bench_config.actuators) options.start_positions.push_back(a.initial_position);
  transfer::testing::ServerThread server(bench, options);
  io::RunSpec spec = io::LoadRunSpec(kExample + "emulated.yaml");
  const auto port = server.port();
  spec.substructures.at(0).physical->transfer = {"remote", [port] {
    transfer::BenchClientOptions o;
    o.port = port;
    return std::make_unique<transfer::BenchClient>(o);
  }};
  spec.output.files = false;
  spec.quiet = true;
  spec.scheme.duration = 2.0;  // 4,000 round trips
  spec.scheme.steps = 2000;
  Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const StepResult r = session.Run();
  ASSERT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  const auto numerical = RunInMemory(kExample + "dummy.yaml");
  ASSERT_EQ(recorder.rows.size(), 2001u);
  double worst = 0.0;
  for (std::size_t i = 0; i < recorder.rows.size(); ++i) {
    for (std::size_t j = 0; j < 4; ++j) {
      worst = std::max(worst, std::abs(recorder.rows[i][j] - numerical[i][j]));
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(server.server().commands_received(), 4001);
}

TEST(MultiActuatorSession, WrongCouplingIsSeen) {
  // The same bench against a numerical block that ignores the coupling (diag of Tᵀ K T):
  // the contract comparison must fail by far more than its tolerance.
  io::RunSpec spec = io::LoadRunSpec(kExample + "dummy.yaml");
  ASSERT_EQ(spec.substructures.size(), 1u);
  Eigen::MatrixXd diag = spec.substructures[0].stiffness->diagonal().asDiagonal();
  spec.substructures[0].stiffness = diag;
  spec.output.files = false;
  spec.quiet = true;
  Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  ASSERT_EQ(session.Run().status, SessionStatus::kFinished);
  const auto physical = RunInMemory(kExample + "emulated.yaml");
  double worst = 0.0;
  for (std::size_t i = 0; i < physical.size(); ++i) {
    worst = std::max(worst, std::abs(physical[i][0] - recorder.rows[i][0]));
  }
  EXPECT_GT(worst, 1e-4);
}

TEST(MultiActuatorSession, JournalHasOneChannelGroupPerActuator) {
  const io::RunSpec spec = io::LoadRunSpec(kExample + "emulated.yaml");
  std::vector<std::string> names;
  for (const auto& c : JournalChannels(spec)) names.push_back(c.name);
  const std::vector<std::string> expected{
      "t", "q_flap", "q_edge", "u1", "u2", "r_flap", "r_edge",
      "blade1_a1_command", "blade1_a1_position", "blade1_a1_force", "blade1_a1_lab_time",
      "blade1_a2_command", "blade1_a2_position", "blade1_a2_force", "blade1_a2_lab_time"};
  EXPECT_EQ(names, expected);
}

substructures::LinearSetup ExampleSetup() {
  substructures::LinearSetup s;
  s.p0 = Eigen::Vector2d(0.02, 0.03);
  s.transform.resize(2, 2);
  s.transform << 1.0, 0.0, 0.6, 0.8;
  s.load_cell_zero = Eigen::Vector2d::Zero();
  return s;
}

TEST(PhysicalSubstructure, MeasuredK0IsTheTransformedSpecimenStiffness) {
  const auto bench = transfer::LoadEmulatedBenchSpec(kExample + "bench-2act.yaml");
  transfer::SafetyLimits limits;
  limits.max_increment = 0.002;
  substructures::PhysicalSubstructure sub(
      "blade1", std::make_unique<transfer::EmulatedBench>(bench), ExampleSetup(),
      {limits, limits});
  sub.Activate();
  const auto m = sub.MeasureInitialStiffness(1e-3);
  Eigen::Matrix2d expected;
  expected << 7520.0, 2400.0, 2400.0, 1920.0;
  EXPECT_LT((m.k0 - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
  EXPECT_NEAR(m.actuator_k(0, 1), 1200.0, 1e-6);
  // Each actuator ramped in turn: 4 up and 4 down each.
  EXPECT_EQ(sub.evaluations(), 16);
  ASSERT_TRUE(sub.initial_stiffness());
}

TEST(SafetyGate, OneRefusedCommandMovesNoActuator) {
  const auto bench_config = transfer::LoadEmulatedBenchSpec(kExample + "bench-2act.yaml");
  transfer::EmulatedBench bench(bench_config);
  bench.Activate();
  transfer::SafetyLimits limits;
  limits.stroke_min = -0.1;
  limits.stroke_max = 0.1;
  limits.max_increment = 0.005;
  transfer::SafetyGate gate({limits, limits});
  gate.monitor(0).SetStartPosition(0.02);
  gate.monitor(1).SetStartPosition(0.03);
  std::vector<transfer::GatedMove> out;
  gate.Move(bench, {0.021, 0.031}, {0, 0}, {0.0, 0.0}, out);
  EXPECT_NEAR(bench.actuator_position(0), 0.021, 1e-12);
  // Actuator 2 would step by 9 mm: refused, and actuator 1 stays where it was.
  EXPECT_THROW(gate.Move(bench, {0.022, 0.040}, {1, 0}, {0.0, 0.0}, out), transfer::SafetyStop);
  EXPECT_NEAR(bench.actuator_position(0), 0.021, 1e-12);
  EXPECT_NEAR(bench.actuator_position(1), 0.031, 1e-12);
  EXPECT_EQ(*bench.commands_received(), 1);
  // The monitors did not learn the refused vector: a move from the accepted one passes.
  gate.Move(bench, {0.022, 0.032}, {2, 0}, {0.0, 0.0}, out);
  EXPECT_NEAR(out[1].force, 1200.0 * 0.002 + 3000.0 * 0.002, 1e-9);
}

TEST(MultiActuatorConfig, RankDeficientTransformIsAConfigError) {
  auto s = ExampleSetup();
  s.transform << 1.0, 2.0, 0.5, 1.0;
  EXPECT_THROW(s.Validate(), ConfigError);
}

}  // namespace
}  // namespace hybridtest::runner
