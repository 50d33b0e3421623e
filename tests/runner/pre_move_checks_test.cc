// The checks before moving (pre_move_checks.h) are the Session's own: a spec with a step beyond
// the scheme's stability limit, or a setup.p0 that disagrees with what the bench announces, is
// refused when the Session is built — before the transfer system is activated or receives a
// command — unless the caller opts out (SessionOptions::pre_move_checks).
#include "hybridtest/runner/pre_move_checks.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::runner {
namespace {

// What the bench saw.
struct Calls {
  int activate = 0;
  int execute = 0;
};

// A spring bench (SI) that announces its zero-force position and counts what it receives.
class CountingSpring final : public transfer::TransferSystem {
 public:
  CountingSpring(std::shared_ptr<Calls> calls, double p0) : calls_(std::move(calls)), p0_(p0) {}
  void Activate() override { ++calls_->activate; }
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<transfer::Measurement> out) override {
    transfer::RequireOneActuator(commands, out, "counting spring");
    ++calls_->execute;
    out[0] = {commands[0], 7200.0 * (commands[0] - p0_)};
  }
  void Hold() noexcept override {}
  void Deactivate() override {}
  transfer::BenchUnits bench_units() const override { return {}; }
  std::string Describe() const override { return "counting spring"; }
  transfer::BenchAnnouncement Announce() const override { return {{{p0_, std::nullopt}}, "the spring"}; }

 private:
  std::shared_ptr<Calls> calls_;
  double p0_;
};

// The paper's rotor, blade 1 behind the counting spring (setup.p0 = 0.02 m), heun at `dt`.
io::RunSpec Spec(double dt, double bench_p0, const std::shared_ptr<Calls>& calls) {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {name: rotor, blades: 3}\n"
      "integrator: {tableau: heun, dt: " + std::to_string(dt) + "}\n"
      "duration: 0.02\n"
      "substructures:\n  r1:\n    type: physical\n"
      "    transfer: {type: loopback, law: {type: linear, stiffness: 7200}}\n"
      "    setup: {p0: 0.02}\n"
      "    safety: {stroke_min: -0.15, stroke_max: 0.15, max_increment: 0.005,\n"
      "             force_soft: 8000, force_hard: 10000, timeout: 5}\n",
      "pre_move_checks_test.yaml")));
  spec.output.files = false;
  spec.substructures[0].physical->transfer = {
      "counting", [calls, bench_p0] { return std::make_unique<CountingSpring>(calls, bench_p0); }};
  return spec;
}

std::string RefusalOf(io::RunSpec spec, SessionOptions options = {}) {
  try {
    Session session(std::move(spec), std::move(options));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SessionPreMoveChecks, AStepBeyondTheStabilityLimitIsRefusedBeforeTheBenchIsTouched) {
  auto calls = std::make_shared<Calls>();
  const std::string message = RefusalOf(Spec(0.004, 0.02, calls));
  EXPECT_NE(message.find("pre_move_checks_test.yaml:2: integrator.dt = 0.004 s is beyond the "
                         "stability limit of heun"), std::string::npos) << message;
  EXPECT_EQ(calls->activate, 0);
  EXPECT_EQ(calls->execute, 0);
  // The largest stable step it names, which the step it refuses exceeds and the paper's 1 ms
  // does not.
  const io::RunSpec spec = Spec(0.001, 0.02, calls);
  const double h_max = CheckSchemeStability(spec);
  EXPECT_GT(h_max, 0.001);
  EXPECT_LT(h_max, 0.004);
  EXPECT_NE(message.find(fmt::format("Choose dt ≤ {:.4g} s", h_max)), std::string::npos);
}

TEST(SessionPreMoveChecks, AP0ThatDisagreesWithTheBenchIsRefusedBeforeTheBenchIsTouched) {
  auto calls = std::make_shared<Calls>();
  const std::string message = RefusalOf(Spec(0.001, 0.03, calls));
  EXPECT_NE(message.find("substructures.r1.setup.p0 = 0.02 m, but the spring announces p0 = "
                         "0.03 m"), std::string::npos) << message;
  EXPECT_NE(message.find("Nothing was sent to the bench"), std::string::npos);
  EXPECT_EQ(calls->activate, 0);
  EXPECT_EQ(calls->execute, 0);
  // Within a tenth of max_increment (0.5 mm) the setup agrees, and the run goes.
  Session agreeing(Spec(0.001, 0.0204, calls));
  EXPECT_EQ(agreeing.Run().status, SessionStatus::kFinished);
  EXPECT_EQ(calls->activate, 1);
  EXPECT_GT(calls->execute, 0);
}

// The two-actuator blade of example 06 on its emulated bench (p0_mm: [20, 30]), with
// actuator 2's setup.p0 `p0_2` [m] and actuator 2's stroke_max `stroke_2` [m].
io::RunSpec BladeSpec(const std::string& p0_2, const std::string& stroke_2) {
  const std::string dir = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/06_blade_two_actuators/";
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {file: " + dir + "blade_tip.yaml}\n"
      "integrator: {tableau: heun, dt: 0.001}\n"
      "duration: 0.01\n"
      "substructures:\n  blade1:\n    type: physical\n    slots: [r_flap, r_edge]\n"
      "    transfer: {type: emulated, config: " + dir + "bench-2act.yaml}\n"
      "    setup: {p0: [0.02, " + p0_2 + "], transform: [[1.0, 0.0], [0.6, 0.8]]}\n"
      "    safety: {stroke_min: -0.10, stroke_max: [0.10, " + stroke_2 + "],\n"
      "             max_increment: 0.002, force_soft: 2000, force_hard: 3000, timeout: 5}\n",
      "blade_test.yaml")));
  spec.output.files = false;
  return spec;
}

TEST(SessionPreMoveChecks, EachActuatorOfABenchOfTwoIsChecked) {
  // Actuator 2 set up 5 mm from where the bench's specimen is at rest.
  std::string message = RefusalOf(BladeSpec("0.035", "0.10"));
  EXPECT_NE(message.find("substructures.blade1.setup.p0[2] = 0.035 m, but the emulated bench "
                         "announces p0 = 0.03 m (p0_mm: 30) for actuator 2"),
            std::string::npos) << message;
  EXPECT_NE(message.find("Set substructures.blade1.setup.p0[2]: 0.03"), std::string::npos)
      << message;
  // Actuator 2's stroke beyond the bench's 150 mm.
  message = RefusalOf(BladeSpec("0.03", "0.2"));
  EXPECT_NE(message.find("substructures.blade1.safety[2].stroke_max = 0.2 m is beyond the limit "
                         "the emulated bench for actuator 2 announces"),
            std::string::npos) << message;
  // As the example sets it up, it runs.
  Session agreeing(BladeSpec("0.03", "0.10"));
  EXPECT_EQ(agreeing.Run().status, SessionStatus::kFinished);
}

TEST(SessionPreMoveChecks, ACallerMayOptOut) {
  auto calls = std::make_shared<Calls>();
  SessionOptions options;
  options.pre_move_checks = false;
  EXPECT_EQ(RefusalOf(Spec(0.001, 0.03, calls), options), "");
  Session session(Spec(0.001, 0.03, calls), options);
  EXPECT_EQ(session.Run().status, SessionStatus::kFinished);
  EXPECT_GT(calls->execute, 0);
}

}  // namespace
}  // namespace hybridtest::runner
