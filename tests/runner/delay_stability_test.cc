// The delay stability check against the closed form of one mass (Horiuchi et al. 1999):
// m ẍ + c ẋ + k_N x + k_E x(t − τ) = 0 crosses at (mω² − k_N)² + (cω)² = k_E², for
// τ_c = atan2(cω, mω² − k_N)/ω.
#include "hybridtest/runner/delay_stability.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::runner {
namespace {

constexpr double kM = 2.0, kC = 3.0, kN = 500.0, kE = 7200.0;

std::string ModelFile() {
  const auto path = std::filesystem::temp_directory_path() / "hybridtest_delay_oscillator.yaml";
  std::ofstream(path) << R"(name: oscillator
description: one mass on a numerical spring and damper and the specimen
parameters:
  m:  {value: 2.0, unit: kg, description: mass}
  c:  {value: 3.0, unit: N·s/m, description: damping}
  kn: {value: 500.0, unit: N/m, description: numerical stiffness}
  ke: {value: 7200.0, unit: N/m, description: specimen stiffness}
coordinates:
  - {name: x, unit: m, description: displacement}
speeds:
  - {name: v, unit: m/s, description: velocity}
frames: []
points:
  - {name: P, from: O, frame: N, position: [x, 0, 0]}
particles:
  - {name: mass, point: P, mass: m}
slots:
  - {name: r1, unit: N, description: specimen force, displacement: x, stiffness: ke}
forces:
  - {name: spring, point: P, value: [-r1 - c * v - kn * x, 0, 0]}
torques: []
)";
  return path.string();
}

io::RunSpec Spec(double delay, bool force) {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {file: " + ModelFile() + "}\n"
      "integrator: {scheme: alpha-os, dt: 0.0001}\n"
      "duration: 0.01\n"
      "real_time: {force: " + std::string(force ? "true" : "false") + "}\n"
      "substructures:\n  r1:\n    type: physical\n    initial_stiffness: 7200\n"
      "    transfer: {type: rt_plant, plant: ideal, delay: " + std::to_string(delay) +
      ", specimen: {stiffness: 7200}}\n"
      "    safety: defaults\n",
      "delay_stability_test.yaml")));
  spec.output.files = false;
  return spec;
}

TEST(DelayStability, OneMassMatchesTheClosedForm) {
  // ω² from m²ω⁴ + (c² − 2 m k_N) ω² + k_N² − k_E² = 0.
  const double b = kC * kC - 2.0 * kM * kN;
  const double w2 = (-b + std::sqrt(b * b - 4.0 * kM * kM * (kN * kN - kE * kE))) / (2.0 * kM * kM);
  const double w = std::sqrt(w2);
  const double tau = std::atan2(kC * w, kM * w2 - kN) / w;
  Session session(Spec(0.001, true));  // beyond τ_c: built only when forced
  const auto margins = CheckDelayStability(session);
  ASSERT_EQ(margins.size(), 1u);
  EXPECT_NEAR(margins[0].critical_delay, tau, 1e-6 * tau);
  EXPECT_NEAR(margins[0].crossing_hz * 2.0 * std::acos(-1.0), w, 1e-6 * w);
  EXPECT_NEAR(margins[0].plant_delay, 0.001, 1e-9);
  EXPECT_EQ(margins[0].unstable(), 0.001 > tau);
  EXPECT_LT(tau, 0.001);  // c/k_E ≈ 0.42 ms: 1 ms is beyond it
}

TEST(DelayStability, AnUnstableRunIsRefusedUnlessForced) {
  // The session makes the check as it builds its pacer, before anything moves.
  try {
    Session refused(Spec(0.001, false));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("critical delay"), std::string::npos) << e.what();
  }
  Session forced(Spec(0.001, true));
  EXPECT_NO_THROW(RefuseUnstable(forced, CheckDelayStability(forced)));
  Session short_delay(Spec(0.0001, false));
  EXPECT_NO_THROW(RefuseUnstable(short_delay, CheckDelayStability(short_delay)));
}

}  // namespace
}  // namespace hybridtest::runner
