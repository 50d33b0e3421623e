// The delay check of a specimen on two actuators (its coupled loop: both actuators lag) against
// the modes of the delayed system. Two masses m with dampers c, no numerical spring, on one
// specimen K = [[k, κ], [κ, k]] through T = I: m ẍ + c ẋ + K x(t − τ) = 0 splits into the modes
// (1, ±1) of stiffness k ± κ, each m ẍ + c ẋ + k_E x(t − τ) = 0, whose critical delay is
// atan2(cω, mω²)/ω at m²ω⁴ + c²ω² = k_E² (Horiuchi et al. 1999). The run's τ_c is the smaller.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/delay_stability.h"

namespace hybridtest::runner {
namespace {

constexpr double kMass = 2.0, kDamping = 3.0, kK = 1000.0, kKappa = 900.0;

std::string TwoMassModel() {
  const auto path = std::filesystem::temp_directory_path() / "hybridtest_delay_two_masses.yaml";
  std::ofstream(path) << R"(name: two_masses
description: two masses with dampers on one specimen of two actuators
parameters:
  m: {value: 2.0, unit: kg, description: mass}
  c: {value: 3.0, unit: N·s/m, description: damping}
  k: {value: 1000.0, unit: N/m, description: default slot stiffness}
coordinates:
  - {name: x1, unit: m, description: first mass}
  - {name: x2, unit: m, description: second mass}
points:
  - {name: P1, from: O, frame: N, position: [x1, 0, 0]}
  - {name: P2, from: O, frame: N, position: [0, x2, 0]}
particles:
  - {name: mass1, point: P1, mass: m}
  - {name: mass2, point: P2, mass: m}
slots:
  - {name: r1, unit: N, description: specimen force 1, displacement: x1, stiffness: k}
  - {name: r2, unit: N, description: specimen force 2, displacement: x2, stiffness: k}
forces:
  - {name: f1, point: P1, value: [-r1 - c * u1, 0, 0]}
  - {name: f2, point: P2, value: [0, -r2 - c * u2, 0]}
torques: []
)";
  return path.string();
}

double ModeCriticalDelay(double ke) {
  const double w2 = (-kDamping * kDamping +
                     std::sqrt(std::pow(kDamping, 4) + 4.0 * kMass * kMass * ke * ke)) /
                    (2.0 * kMass * kMass);
  const double w = std::sqrt(w2);
  return std::atan2(kDamping * w, kMass * w2) / w;
}

TEST(DelayStabilityCoupled, TwoActuatorsDelayedTogetherMatchTheModes) {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {file: " + TwoMassModel() + "}\n"
      "integrator: {scheme: alpha-os, dt: 0.0001}\n"
      "duration: 0.01\n"
      "real_time: {force: true}\n"
      "substructures:\n  s:\n    type: physical\n    slots: [r1, r2]\n"
      "    initial_stiffness: [[1000, 900], [900, 1000]]\n"
      "    transfer: {type: rt_plant, plant: ideal, actuators: 2, delay: 0.002,\n"
      "               specimen: {stiffness: [[1000, 900], [900, 1000]]}}\n"
      "    setup: {p0: [0, 0], transform: [[1, 0], [0, 1]]}\n"
      "    safety: defaults\n",
      "delay_stability_coupled_test.yaml")));
  spec.output.files = false;
  Session session(spec);
  const auto margins = CheckDelayStability(session);
  ASSERT_EQ(margins.size(), 2u);
  const double tau = std::min(ModeCriticalDelay(kK + kKappa), ModeCriticalDelay(kK - kKappa));
  for (const SlotDelayMargin& g : margins) {
    EXPECT_EQ(g.delayed_together, 2) << g.slot;
    EXPECT_NEAR(g.critical_delay, tau, 1e-6 * tau) << g.slot;
    EXPECT_NEAR(g.plant_delay, 0.002, 1e-12) << g.slot;
    EXPECT_TRUE(g.unstable()) << g.slot;  // 2 ms against τ_c ≈ 1.58 ms (the mode k + κ)
  }
}

}  // namespace
}  // namespace hybridtest::runner
