// The bench with several actuators on one specimen: its coupled nonlinear specimen, its state,
// and the force prediction that couples the actuators (the gate group's and the bench's own).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen_biaxial.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/safety_gate.h"

namespace hybridtest::transfer {
namespace {

// An ideal bench of two actuators at p0 = 0 (mm on the wire) with `specimen` and bench limits.
EmulatedBenchSpec Bench(const std::string& specimen, double force_soft_kN = 8.0) {
  const std::string text = R"(
bench:
  actuators: 2
  units: {length: mm, force: N}
  pacing: accelerated
  p0_mm: [0, 0]
  specimen: )" + specimen + R"(
  actuator: {position_min_mm: -150, position_max_mm: 150, capacity_kN: 10, lag: {type: none},
             delay_ms: 0, velocity_limit_mm_per_s: 1000}
  load_cell: {noise_std_N: [0, 0], resolution_N: 0, offset_N: 0}
  settling: {tolerance_mm: 0.001, dwell_ms: 0}
  sampling: {window_ms: 1}
  timing: {overhead_ms: 0, internal_step_ms: 1}
  safety: {stroke_min_mm: -150, stroke_max_mm: 150, max_increment_mm: 50,
           force_soft_kN: )" + std::to_string(force_soft_kN) + R"(, force_hard_kN: 10, timeout_s: 5}
)";
  return ParseEmulatedBenchSpec(YAML::Load(text)["bench"], "bench");
}

const char* kBoucWen =
    "{type: bouc_wen_biaxial, initial_stiffness: [5000, 3000], yield_displacement: [0.002, 0.004], "
    "alpha: 0.1}";
const char* kCoupled = "{type: linear, stiffness: [[5000, 4500], [4500, 5000]]}";

std::array<Measurement, 2> Move(TransferSystem& bench, double a1_mm, double a2_mm) {
  std::array<Measurement, 2> out{};
  const std::array<double, 2> c{a1_mm, a2_mm};
  bench.Execute(c, out);
  return out;
}

// An ideal bench measures the law along the actuators' path: each command's forces are the
// law's after the straight path from the last position (the actuators arrive together only
// when their moves take equally long; here one axis moves at a time, or both by equal steps).
TEST(EmulatedBenchOfSeveral, BoucWenSpecimenIsMeasuredAsTheLaw) {
  EmulatedBench bench(Bench(kBoucWen));
  bench.Activate();
  constitutive::BoucWenBiaxial::Parameters p;
  p.initial_stiffness = {5000, 3000};
  p.yield_displacement = {0.002, 0.004};
  p.alpha = 0.1;
  constitutive::BoucWenBiaxial law(p);
  double worst = 0.0, peak = 0.0, f1_at_40 = 0.0, f1_at_80 = 0.0;
  std::array<double, 2> f{};
  for (int i = 1; i <= 120; ++i) {
    // Along actuator 1 out to 8 mm, then along actuator 2 out to 8 mm, then both back.
    const double a1 = i <= 40 ? 0.2 * i : (i <= 80 ? 8.0 : 8.0 - 0.2 * (i - 80));
    const double a2 = i <= 40 ? 0.0 : (i <= 80 ? 0.2 * (i - 40) : 8.0 - 0.2 * (i - 80));
    const auto m = Move(bench, a1, a2);
    const std::array<double, 2> u{a1 * 1e-3, a2 * 1e-3};
    law.Trial(u, f);
    law.Commit();
    if (i == 40) f1_at_40 = m[0].force;
    if (i == 80) f1_at_80 = m[0].force;
    for (int k = 0; k < 2; ++k) {
      worst = std::max(worst, std::abs(m[static_cast<std::size_t>(k)].force - f[static_cast<std::size_t>(k)]));
      peak = std::max(peak, std::abs(f[static_cast<std::size_t>(k)]));
    }
  }
  // The bench integrates along 1 ms internal steps, the law along each command's path: the
  // same path, sub-stepped differently.
  EXPECT_LT(worst, 1e-6 * peak);
  // Actuator 1 held still while actuator 2 yielded, and its force fell: the specimen couples
  // them (z turns from actuator 1 towards actuator 2: 4 + 9 tanh(4) → 4 + 9 / cosh(2) N).
  EXPECT_NEAR(f1_at_40, 4.0 + 9.0 * std::tanh(4.0), 0.05);
  EXPECT_LT(f1_at_80, 0.6 * f1_at_40);
  EXPECT_NE(bench.Describe().find("Bouc-Wen"), std::string::npos);
}

TEST(EmulatedBenchOfSeveral, SaveAndRestoreContinueIdentically) {
  EmulatedBench a(Bench(kBoucWen));
  a.Activate();
  for (int i = 1; i <= 30; ++i) Move(a, 0.3 * i, -0.2 * i);
  const nlohmann::json saved = a.SaveState();
  EmulatedBench b(Bench(kBoucWen));
  b.Activate();
  b.RestoreState(saved);
  EXPECT_EQ(*b.commands_received(), 30);
  EXPECT_DOUBLE_EQ(b.lab_time(), a.lab_time());
  for (int i = 1; i <= 30; ++i) {
    const auto ma = Move(a, 9.0 - 0.5 * i, -6.0 + 0.4 * i);
    const auto mb = Move(b, 9.0 - 0.5 * i, -6.0 + 0.4 * i);
    for (std::size_t k = 0; k < 2; ++k) {
      ASSERT_EQ(ma[k].force, mb[k].force) << i;
      ASSERT_EQ(ma[k].position, mb[k].position) << i;
    }
  }
  // A fresh bench without the state measures something else (the test can fail).
  EmulatedBench c(Bench(kBoucWen));
  c.Activate();
  EXPECT_NE(Move(c, 8.5, -5.6)[0].force, Move(b, 8.5, -5.6)[0].force);
  EXPECT_THROW(c.RestoreState({{"kind", "emulated"}}), Error);
}

// ReadAll reads where the actuators are and what the specimen carries there, without moving
// and without touching the specimen's committed (hysteretic) state.
TEST(EmulatedBenchOfSeveral, ReadAllReadsWithoutMovingOrDeforming) {
  EmulatedBench a(Bench(kBoucWen));
  EmulatedBench b(Bench(kBoucWen));
  a.Activate();
  b.Activate();
  std::array<Measurement, 2> last{};
  for (int i = 1; i <= 20; ++i) {
    last = Move(a, 0.4 * i, -0.3 * i);
    Move(b, 0.4 * i, -0.3 * i);
  }
  const auto read = a.ReadAll();
  ASSERT_TRUE(read.has_value());
  ASSERT_EQ(read->size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NEAR((*read)[k].position, last[k].position, 1e-9) << k;  // [mm]
    EXPECT_NEAR((*read)[k].force, last[k].force, 1e-9 * std::abs(last[k].force)) << k;
  }
  EXPECT_EQ(*a.commands_received(), 20);
  // The read left the specimen as it was: both benches go on identically.
  for (int i = 1; i <= 10; ++i) {
    const auto ma = Move(a, 8.0 - 1.1 * i, -6.0 + 0.9 * i);
    const auto mb = Move(b, 8.0 - 1.1 * i, -6.0 + 0.9 * i);
    for (std::size_t k = 0; k < 2; ++k) ASSERT_EQ(ma[k].force, mb[k].force) << i;
  }
}

SafetyLimits Limits() {
  SafetyLimits l;
  l.max_increment = 0.05;
  l.force_soft = 100.0;
  l.force_hard = 10e3;
  return l;
}

// K = [[5000, 4500], [4500, 5000]] N/m: moving both actuators together loads each by
// 9500 N/m, moving them against each other by 500 N/m. A diagonal prediction (5000 N/m) gets
// both wrong.
TEST(SafetyGateOfSeveral, CoupledPredictionUsesTheOffDiagonalStiffness) {
  Eigen::Matrix2d k;
  k << 5000, 4500, 4500, 5000;
  auto gate_for = [&](bool coupled) {
    SafetyGate gate({Limits(), Limits()});
    for (int i = 0; i < 2; ++i) {
      gate.monitor(i).SetStartPosition(0.0);
      gate.monitor(i).SetInitialStiffness(5000.0);
    }
    if (coupled) gate.SetStiffness(k);
    return gate;
  };
  std::vector<GatedMove> out;
  for (const bool coupled : {false, true}) {
    // Together: 12 mm each predicts 60 N (diagonal) or 114 N (coupled) against 100 N.
    {
      EmulatedBench bench(Bench(kCoupled, 1.0));
      bench.Activate();
      auto gate = gate_for(coupled);
      gate.Move(bench, {0.0, 0.0}, {0, 0}, {0.0, 0.0}, out);
      if (coupled) {
        EXPECT_NEAR(gate.PredictForces({0.012, 0.012})(0), 114.0, 1e-9);
        try {
          gate.Move(bench, {0.012, 0.012}, {1, 0}, {0.0, 0.0}, out);
          ADD_FAILURE() << "the coupled prediction lets 114 N through";
        } catch (const SafetyStop& e) {
          EXPECT_EQ(e.limit(), "force_soft");
          EXPECT_NEAR(e.value(), 114.0, 1e-9);
          EXPECT_NE(std::string(e.what()).find("coupled"), std::string::npos) << e.what();
        }
        EXPECT_EQ(*bench.commands_received(), 1);  // nothing moved
      } else {
        EXPECT_NO_THROW(gate.Move(bench, {0.012, 0.012}, {1, 0}, {0.0, 0.0}, out));
        EXPECT_NEAR(out[0].force, 114.0, 1e-9);  // what the diagonal missed
      }
    }
    // Against each other: 25 mm predicts 125 N (diagonal) or 12.5 N (coupled).
    {
      EmulatedBench bench(Bench(kCoupled, 1.0));
      bench.Activate();
      auto gate = gate_for(coupled);
      gate.Move(bench, {0.0, 0.0}, {0, 0}, {0.0, 0.0}, out);
      if (coupled) {
        gate.Move(bench, {0.025, -0.025}, {1, 0}, {0.0, 0.0}, out);
        EXPECT_NEAR(out[0].force, 12.5, 1e-9);
      } else {
        EXPECT_THROW(gate.Move(bench, {0.025, -0.025}, {1, 0}, {0.0, 0.0}, out), SafetyStop);
      }
    }
  }
  SafetyGate gate({Limits(), Limits()});
  EXPECT_THROW(gate.SetStiffness(Eigen::Matrix3d::Identity()), ConfigError);
}

// The bench's own monitors predict with the specimen's stiffness matrix too.
TEST(EmulatedBenchOfSeveral, OwnSafetyPredictsWithTheCoupledStiffness) {
  EmulatedBench bench(Bench(kCoupled, 0.1));  // force_soft 100 N
  bench.Activate();
  Move(bench, 0.0, 0.0);
  try {
    Move(bench, 12.0, 12.0);  // 60 N on the diagonal, 114 N coupled
    ADD_FAILURE() << "the bench let 114 N through";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "force_soft");
  }
  EmulatedBench apart(Bench(kCoupled, 0.1));
  apart.Activate();
  Move(apart, 0.0, 0.0);
  EXPECT_NEAR(Move(apart, 25.0, -25.0)[0].force, 12.5, 1e-9);
}

TEST(EmulatedBenchSpec, AMissingBenchMappingIsAConfigErrorThatNamesIt) {
  // A file without `bench:` (its top level as the loader reads it): an invalid node, on which
  // yaml-cpp's IsMap() would throw its own InvalidNode.
  const YAML::Node root = YAML::Load("benc: {actuators: 2}\n");
  const YAML::Node& top = root;
  try {
    (void)ParseEmulatedBenchSpec(static_cast<const YAML::Node&>(top)["bench"], "b.yaml: bench");
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("b.yaml: bench"), std::string::npos) << e.what();
  }
}

TEST(EmulatedBenchSpec, ASeedThatIsNotAnIntegerIsAConfigErrorThatNamesIt) {
  for (const char* seed : {":1", "-1", "1.5", "[1, x]"}) {
    const YAML::Node bench = YAML::Load(std::string("actuators: 2\nseed: ") + seed +
                                        "\nspecimen: {type: linear, stiffness: [[5000, 0], [0, "
                                        "3000]]}\np0_mm: [20, 30]\n");
    try {
      (void)ParseEmulatedBenchSpec(bench, "b.yaml: bench");
      ADD_FAILURE() << seed;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("b.yaml: bench"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace hybridtest::transfer
