// The paced loop in virtual time: with the ideal plant it is the pseudo-dynamic run; with the
// servo-hydraulic plant it is reproducible and its J1 is the plant's delay.
#include "hybridtest/runner/paced_loop.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::runner {
namespace {

const std::string kModel = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/real-time/storey.model.yaml";

std::string Config(const std::string& slot, bool real_time, const std::string& scheme =
                                                                "{scheme: alpha-os, dt: 0.001}") {
  return "model: {file: " + kModel + "}\n"
         "initial_state: {q: [0.001, 0.0, -0.001], u: [0.0, 0.0, 0.0]}\n"
         "integrator: " + scheme + "\n"
         "duration: 0.5\n" +
         (real_time ? "real_time: {hold_after_misses: 0}\n" : "") +
         "substructures:\n  r1:\n" + slot;
}

const std::string kIdealPlant =
    "    type: physical\n"
    "    initial_stiffness: 1.19e6\n"
    "    transfer: {type: rt_plant, plant: ideal, specimen: {stiffness: 1.19e6}}\n"
    "    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.01, force_soft: 1e6, "
    "force_hard: 2e6, timeout: 1}\n";

io::RunSpec Spec(const std::string& text, const std::string& clock = "") {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(
      YamlInput::FromText(text, std::string(HYBRIDTEST_SOURCE_DIR) + "/tests/paced.yaml")));
  spec.output.files = false;
  spec.quiet = true;
  spec.real_time.clock = clock;
  return spec;
}

class States final : public SessionObserver {
 public:
  void OnCommit(const CommitEvent& e) override {
    if (e.kind == RowKind::kCommitted) x.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> x;
};

std::vector<std::vector<double>> RunPaced(const std::string& text, PacedStatistics* stats = nullptr,
                                          nlohmann::json* json = nullptr) {
  // The Session builds its pacer from the spec: the virtual clock it names.
  Session session(Spec(text, "virtual"));
  States states;
  session.AddObserver(states);
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  const PacedLoop* loop = session.paced_loop();
  EXPECT_NE(loop, nullptr);
  if (loop == nullptr) return states.x;
  EXPECT_EQ(loop->clock_name(), "virtual");
  if (stats != nullptr) *stats = loop->statistics();
  if (json != nullptr) *json = loop->ToJson();
  return states.x;
}

std::vector<std::vector<double>> RunSettled(const std::string& text) {
  Session session(Spec(text));
  States states;
  session.AddObserver(states);
  const StepResult r = session.Run();
  EXPECT_EQ(r.status, SessionStatus::kFinished) << r.reason;
  return states.x;
}

double MaxDifference(const std::vector<std::vector<double>>& a,
                     const std::vector<std::vector<double>>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    for (std::size_t j = 0; j < a[i].size(); ++j) d = std::max(d, std::abs(a[i][j] - b[i][j]));
  }
  return d;
}

TEST(PacedLoop, IdealPlantInVirtualTimeIsThePseudoDynamicRun) {
  const auto paced = RunPaced(Config(kIdealPlant, true));
  const auto settled = RunSettled(Config(kIdealPlant, false));
  const auto numerical =
      RunSettled(Config("    type: numerical\n    law: {type: linear, stiffness: 1.19e6}\n", false));
  ASSERT_EQ(paced.size(), 501u);
  EXPECT_LE(MaxDifference(paced, settled), 1e-9);
  EXPECT_LE(MaxDifference(paced, numerical), 1e-9);
  // The run moved: the comparison is not between two states at rest.
  EXPECT_GT(std::abs(paced.back()[0] - paced.front()[0]), 1e-5);
}

TEST(PacedLoop, APlantDelayChangesTheRunAndShowsAsJ1) {
  const std::string delayed =
      "    type: physical\n"
      "    initial_stiffness: 1.19e6\n"
      "    transfer: {type: rt_plant, plant: ideal, delay: 0.004, specimen: {stiffness: 1.19e6}}\n"
      "    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.01, force_soft: 1e6, "
      "force_hard: 2e6, timeout: 1}\n";
  PacedStatistics stats;
  nlohmann::json json;
  const auto x = RunPaced(Config(delayed, true), &stats, &json);
  const auto ideal = RunPaced(Config(kIdealPlant, true));
  EXPECT_GT(MaxDifference(x, ideal), 1e-6);
  EXPECT_EQ(stats.ticks, 500);
  EXPECT_EQ(stats.misses, 0);
  EXPECT_EQ(stats.late_max, 0.0);
  EXPECT_NEAR(json["J1_ms"].get<double>(), 4.0, 0.5);
  EXPECT_GT(json["J2"].get<double>(), 1.0);  // [%]
}

TEST(PacedLoop, ServoHydraulicRunIsBitReproducible) {
  const std::string servo =
      "    type: physical\n"
      "    initial_stiffness: 1.19e6\n"
      "    transfer: {type: rt_plant, plant: electromechanical, lag: 0.002, delay: 0.001, "
      "specimen: {stiffness: 1.19e6, mass: 29.13, zeta: 0.0097}}\n"
      "    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.01, force_soft: 1e6, "
      "force_hard: 2e6, timeout: 1}\n";
  const auto a = RunPaced(Config(servo, true));
  const auto b = RunPaced(Config(servo, true));
  EXPECT_EQ(a, b);
}

TEST(PacedLoop, RefusesASchemeWithSeveralEvaluationsPerStep) {
  EXPECT_THROW(Session(Spec(Config(kIdealPlant, true, "{tableau: heun, dt: 0.001}"), "virtual")),
               ConfigError);
}

TEST(PacedLoop, ATransferThatCannotRunPacedIsRefusedNamingIt) {
  const std::string loopback =
      "    type: physical\n"
      "    initial_stiffness: 1.19e6\n"
      "    transfer: {type: loopback, law: {type: linear, stiffness: 1.19e6}}\n"
      "    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.01, force_soft: 1e6, "
      "force_hard: 2e6, timeout: 1}\n";
  // Refused when the session builds its pacer, before anything moves (decision 0016).
  try {
    Session session(Spec(Config(loopback, true), "virtual"));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("loopback"), std::string::npos) << e.what();
  }
}

TEST(PacedLoop, ClockWithoutRealTimeBlockIsRefused) {
  EXPECT_THROW(Session(Spec(Config(kIdealPlant, false), "virtual")), ConfigError);
  EXPECT_EQ(Session(Spec(Config(kIdealPlant, false))).paced_loop(), nullptr);
}

TEST(PacedLoop, TheSpecsClockIsTheSessionsAndWallIsTheDefault) {
  EXPECT_EQ(Session(Spec(Config(kIdealPlant, true))).paced_loop()->clock_name(), "wall");
  EXPECT_EQ(Session(Spec(Config(kIdealPlant, true), "wall")).paced_loop()->clock_name(), "wall");
  EXPECT_THROW(Session(Spec(Config(kIdealPlant, true), "sundial")), ConfigError);
}

}  // namespace
}  // namespace hybridtest::runner
