// The gate of a specimen on several actuators (safety_gate.h): a refused command vector
// changes no actuator's monitor and moves nothing, and a move does not allocate once the gate
// has seen one (real-time runs move through it at every tick).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/safety_gate.h"
#include "support/alloc_counter.h"

namespace hybridtest::transfer {
namespace {

// Two actuators in SI, position = command, force = K a: allocates nothing per Execute.
class TwoSprings final : public TransferSystem {
 public:
  explicit TwoSprings(Eigen::Matrix2d k) : k_(std::move(k)) {}
  void Activate() override {}
  int num_actuators() const override { return 2; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override {
    ++executed;
    for (int i = 0; i < 2; ++i) {
      out[static_cast<std::size_t>(i)] = {
          commands[static_cast<std::size_t>(i)],
          k_(i, 0) * commands[0] + k_(i, 1) * commands[1], 0.0};
    }
  }
  void Hold() noexcept override {}
  void Deactivate() override {}
  BenchUnits bench_units() const override { return {}; }
  std::string Describe() const override { return "two coupled springs"; }
  int executed = 0;

 private:
  Eigen::Matrix2d k_;
};

SafetyLimits Limits() {
  SafetyLimits l;
  l.stroke_min = -0.1;
  l.stroke_max = 0.1;
  l.max_increment = 0.005;
  l.force_soft = 1000.0;
  l.force_hard = 2000.0;
  return l;
}

Eigen::Matrix2d Coupled() {
  Eigen::Matrix2d k;
  k << 5000, 4500, 4500, 5000;
  return k;
}

SafetyGate GateAtZero(bool coupled) {
  SafetyGate gate({Limits(), Limits()});
  for (int i = 0; i < 2; ++i) {
    gate.monitor(i).SetStartPosition(0.0);
    gate.monitor(i).SetInitialStiffness(5000.0);
  }
  if (coupled) UseCoupledStiffness(gate, Coupled());
  return gate;
}

// Actuator 1's command passes, actuator 2's jumps too far: neither monitor learns either, and
// the next valid vector is checked against the commands accepted before the refusal.
TEST(SafetyGate, ARefusedVectorChangesNoMonitorAndMovesNothing) {
  for (const bool coupled : {false, true}) {
    TwoSprings bench(Coupled());
    SafetyGate gate = GateAtZero(coupled);
    std::vector<GatedMove> out;
    gate.Move(bench, {0.001, 0.001}, {1, 0}, {0.0, 0.0}, out);
    ASSERT_EQ(bench.executed, 1);
    try {
      gate.Move(bench, {0.002, 0.009}, {2, 0}, {0.0, 0.0}, out);
      ADD_FAILURE() << "an 8 mm increment of actuator 2 passed";
    } catch (const SafetyStop& e) {
      EXPECT_EQ(e.limit(), "max_increment");
    }
    EXPECT_EQ(bench.executed, 1) << "nothing moves when one command is refused";
    for (int i = 0; i < 2; ++i) {
      EXPECT_EQ(gate.monitor(i).last_safe_command(), 0.001) << "actuator " << i + 1;
    }
    // 5.5 mm from 0.001 would pass only if actuator 1's monitor had learnt 0.002.
    EXPECT_THROW(gate.Move(bench, {0.0065, 0.001}, {3, 0}, {0.0, 0.0}, out), SafetyStop);
    EXPECT_NO_THROW(gate.Move(bench, {0.005, 0.001}, {3, 0}, {0.0, 0.0}, out));
    EXPECT_EQ(bench.executed, 2);
  }
}

TEST(SafetyGate, MovesOfTwoActuatorsDoNotAllocate) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "allocations cannot be counted here";
  for (const bool coupled : {false, true}) {
    TwoSprings bench(Coupled());
    SafetyGate gate = GateAtZero(coupled);
    std::vector<GatedMove> out;
    std::vector<double> commands{0.0, 0.0};
    const std::vector<double> zero{0.0, 0.0};
    gate.Move(bench, commands, {0, 0}, zero, out);  // warm-up: sizes the gate's buffers
    long step = 1;
    const long allocations = test_support::CountAllocations([&] {
      for (int k = 0; k < 20; ++k, ++step) {
        commands[0] = 0.001 * static_cast<double>(k % 4);
        commands[1] = -0.001 * static_cast<double>(k % 3);
        gate.Move(bench, commands, {step, 0}, zero, out);
      }
    });
    EXPECT_EQ(allocations, 0) << (coupled ? "coupled" : "diagonal") << " prediction";
    EXPECT_EQ(bench.executed, 21);
  }
}

}  // namespace
}  // namespace hybridtest::transfer
