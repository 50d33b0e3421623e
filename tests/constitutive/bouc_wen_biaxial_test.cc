// The coupled Bouc–Wen law (Park, Wen & Ang 1986) against the one-dimensional law, its yield
// surface, an independent integration, and its state.
#include "hybridtest/constitutive/bouc_wen_biaxial.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/parse_vector_law.h"

namespace hybridtest::constitutive {
namespace {

constexpr double kAlpha = 0.1;
const std::vector<double> kK = {5000.0, 3000.0};     // [N/m]
const std::vector<double> kY = {0.002, 0.004};       // [m]

BoucWenBiaxial MakeLaw(double beta = 0.5, double gamma = 0.5) {
  BoucWenBiaxial::Parameters p;
  p.initial_stiffness = kK;
  p.yield_displacement = kY;
  p.alpha = kAlpha;
  p.beta = beta;
  p.gamma = gamma;
  return BoucWenBiaxial(p);
}

std::array<double, 2> Step(BoucWenBiaxial& law, double ux, double uy) {
  std::array<double, 2> f{};
  const std::array<double, 2> u{ux, uy};
  law.Trial(u, f);
  law.Commit();
  return f;
}

// Motion along one axis is the one-dimensional law with n = 2, β' = β/Y², γ' = γ/Y².
TEST(BoucWenBiaxial, MotionAlongOneAxisIsTheUniaxialLaw) {
  for (int axis = 0; axis < 2; ++axis) {
    for (const auto& [beta, gamma] : {std::pair{0.5, 0.5}, std::pair{0.8, 0.2}, std::pair{0.3, -0.1}}) {
      BoucWenBiaxial biaxial = MakeLaw(beta, gamma);
      const double y = kY[static_cast<std::size_t>(axis)];
      BoucWen::Parameters p;
      p.initial_stiffness = kK[static_cast<std::size_t>(axis)];
      p.alpha = kAlpha;
      p.a = 1.0;
      p.n = 2.0;
      p.beta = beta / (y * y);
      p.gamma = gamma / (y * y);
      p.max_substep = y / 200.0;
      BoucWen uniaxial(p);
      double worst = 0.0, peak = 0.0;
      // Growing cycles up to 5 Y, uneven increments (some larger than a sub-step).
      for (int i = 1; i <= 900; ++i) {
        const double x = (0.5 + 4.5 * i / 900.0) * y * std::sin(2.0 * std::numbers::pi * i / 97.0);
        const auto f = Step(biaxial, axis == 0 ? x : 0.0, axis == 1 ? x : 0.0);
        const double r = uniaxial.Trial(x);
        uniaxial.Commit();
        worst = std::max(worst, std::abs(f[static_cast<std::size_t>(axis)] - r));
        peak = std::max(peak, std::abs(r));
        EXPECT_EQ(f[static_cast<std::size_t>(1 - axis)], 0.0);  // nothing on the other axis
      }
      EXPECT_LT(worst, 1e-9 * peak) << "axis " << axis << " beta " << beta;
      // The test means something: the law yielded (the plateau is well below k·x).
      EXPECT_LT(peak, 0.6 * kK[static_cast<std::size_t>(axis)] * 5.0 * y);
    }
  }
}

// A large circular orbit (in v = u / Y) runs on the interaction surface |z| = 1: the
// hysteretic forces never leave the ellipse and reach it.
TEST(BoucWenBiaxial, CircularOrbitRunsOnTheYieldSurface) {
  BoucWenBiaxial law = MakeLaw();
  const double radius = 8.0;  // [Y]
  double largest = 0.0, smallest_late = 2.0;
  const int per_cycle = 400;
  for (int i = 0; i <= 3 * per_cycle; ++i) {
    const double phase = 2.0 * std::numbers::pi * i / per_cycle;
    // Ramp out along x first, then orbit.
    const double ux = radius * kY[0] * std::cos(phase), uy = radius * kY[1] * std::sin(phase);
    const auto f = Step(law, ux, uy);
    const double hx = (f[0] - kAlpha * kK[0] * ux) / ((1.0 - kAlpha) * kK[0] * kY[0]);
    const double hy = (f[1] - kAlpha * kK[1] * uy) / ((1.0 - kAlpha) * kK[1] * kY[1]);
    const double surface = std::hypot(hx, hy);
    largest = std::max(largest, surface);
    if (i > per_cycle) smallest_late = std::min(smallest_late, surface);
  }
  EXPECT_LE(largest, 1.0 + 1e-9);
  // Close to it after the first cycle (z lags the direction of motion: where some
  // v̇_i z_i < 0, |z| falls slightly inside).
  EXPECT_GT(smallest_late, 0.99);
  // A decoupled pair of uniaxial laws leaves it (towards √2 at 45°): the bound is the coupling's.
  std::vector<BoucWen> pair;
  for (std::size_t i = 0; i < 2; ++i) {
    BoucWen::Parameters p;
    p.initial_stiffness = kK[i];
    p.alpha = kAlpha;
    p.n = 2.0;
    p.beta = p.gamma = 0.5 / (kY[i] * kY[i]);
    pair.emplace_back(p);
  }
  double decoupled = 0.0;
  for (int i = 0; i <= 3 * per_cycle; ++i) {
    const double phase = 2.0 * std::numbers::pi * i / per_cycle;
    const double z0 = pair[0].Trial(radius * kY[0] * std::cos(phase)), z1 = pair[1].Trial(radius * kY[1] * std::sin(phase));
    pair[0].Commit();
    pair[1].Commit();
    decoupled = std::max(decoupled, std::hypot(pair[0].committed_z() / kY[0], pair[1].committed_z() / kY[1]));
    (void)z0;
    (void)z1;
  }
  EXPECT_GT(decoupled, 1.3);
}

// Yielding along one axis takes strength from the other: the interaction Park et al. model.
TEST(BoucWenBiaxial, YieldingAlongXUnloadsTheHystereticForceAlongY) {
  BoucWenBiaxial law = MakeLaw();
  std::array<double, 2> f{};
  for (int i = 1; i <= 100; ++i) f = Step(law, 0.0, 5.0 * kY[1] * i / 100.0);
  const double hy_before = f[1] - kAlpha * kK[1] * 5.0 * kY[1];
  EXPECT_GT(hy_before, 0.99 * (1.0 - kAlpha) * kK[1] * kY[1]);  // on the plateau
  for (int i = 1; i <= 100; ++i) f = Step(law, 5.0 * kY[0] * i / 100.0, 5.0 * kY[1]);
  const double hy_after = f[1] - kAlpha * kK[1] * 5.0 * kY[1];
  EXPECT_LT(hy_after, 0.2 * hy_before);  // z turned towards x: little left along y
  EXPECT_GT(f[0] - kAlpha * kK[0] * 5.0 * kY[0], 0.95 * (1.0 - kAlpha) * kK[0] * kY[0]);
}

// RK4 along one trial path against an independent explicit Euler with a million steps.
TEST(BoucWenBiaxial, PathIntegrationMatchesAFineEulerIntegration) {
  BoucWenBiaxial law = MakeLaw(0.7, 0.3);
  Step(law, 1.5 * kY[0], -0.5 * kY[1]);
  const std::array<double, 2> target{-2.0 * kY[0], 3.0 * kY[1]};
  std::array<double, 2> f{};
  law.Trial(target, f);
  // Euler from the committed state.
  double zx = law.committed_z()(0), zy = law.committed_z()(1);
  const double dvx = (target[0] - 1.5 * kY[0]) / kY[0], dvy = (target[1] + 0.5 * kY[1]) / kY[1];
  const int steps = 1000000;
  for (int s = 0; s < steps; ++s) {
    const double h = 0.7 * (std::abs(dvx * zx) + std::abs(dvy * zy)) + 0.3 * (dvx * zx + dvy * zy);
    const double nx = zx + (dvx - zx * h) / steps, ny = zy + (dvy - zy * h) / steps;
    zx = nx;
    zy = ny;
  }
  EXPECT_NEAR(law.trial_z()(0), zx, 1e-5);
  EXPECT_NEAR(law.trial_z()(1), zy, 1e-5);
  EXPECT_NEAR(f[0], kAlpha * kK[0] * target[0] + (1 - kAlpha) * kK[0] * kY[0] * zx, 1e-5 * kK[0] * kY[0]);
}

TEST(BoucWenBiaxial, VirginTangentAndDissipation) {
  BoucWenBiaxial law = MakeLaw();
  const double e = 1e-9;
  std::array<double, 2> f{};
  law.Trial(std::array<double, 2>{e, e}, f);
  EXPECT_NEAR(f[0] / e, kK[0], 1e-3);
  EXPECT_NEAR(f[1] / e, kK[1], 1e-3);
  EXPECT_EQ(law.initial_stiffness()(0, 1), 0.0);
  EXPECT_EQ(law.initial_stiffness()(1, 1), kK[1]);
  // A closed orbit dissipates ∮ F · du > 0.
  double work = 0.0, ux0 = 0.0, uy0 = 0.0;
  std::array<double, 2> f0{};
  for (int i = 1; i <= 400; ++i) {
    const double phase = 2.0 * std::numbers::pi * i / 200.0;
    const double ux = 3.0 * kY[0] * std::sin(phase), uy = 3.0 * kY[1] * (1.0 - std::cos(phase));
    const auto f1 = Step(law, ux, uy);
    if (i > 200) work += 0.5 * ((f0[0] + f1[0]) * (ux - ux0) + (f0[1] + f1[1]) * (uy - uy0));
    f0 = f1;
    ux0 = ux;
    uy0 = uy;
  }
  EXPECT_GT(work, 0.1 * kK[0] * kY[0] * kY[0]);
}

TEST(BoucWenBiaxial, SaveAndRestoreContinueBitIdentically) {
  BoucWenBiaxial a = MakeLaw();
  for (int i = 1; i <= 50; ++i) Step(a, 0.0001 * i, -0.00015 * i);
  BoucWenBiaxial b = MakeLaw();
  b.RestoreState(a.SaveState());
  for (int i = 1; i <= 50; ++i) {
    const auto fa = Step(a, 0.005 - 0.0002 * i, 0.0001 * i);
    const auto fb = Step(b, 0.005 - 0.0002 * i, 0.0001 * i);
    ASSERT_EQ(fa, fb);
  }
  EXPECT_THROW(b.RestoreState({{"law", "bouc_wen"}, {"x", 0}, {"z", 0}}), Error);
}

TEST(BoucWenBiaxial, ParsesPerActuatorListsAndNamesAWrongLength) {
  const auto law = ParseVectorLaw(
      YAML::Load("{type: bouc_wen_biaxial, initial_stiffness: [5000, 3000], "
                 "yield_displacement: 0.002, alpha: 0.1}"), 2, "bench.specimen");
  EXPECT_EQ(law->num_axes(), 2);
  EXPECT_EQ(law->initial_stiffness()(1, 1), 3000.0);
  try {
    ParseVectorLaw(YAML::Load("{type: bouc_wen_biaxial, initial_stiffness: [5000, 3000, 1], "
                              "yield_displacement: 0.002, alpha: 0.1}"), 2, "bench.specimen");
    FAIL() << "a list of 3 for 2 actuators";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bench.specimen.initial_stiffness"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseVectorLaw(YAML::Load("{type: bouc_wen_biaxial, initial_stiffness: 5000, "
                                         "yield_displacement: -1, alpha: 0.1}"), 2, "s"),
               ConfigError);
  EXPECT_THROW(ParseVectorLaw(YAML::Load("{type: bouc_wen}"), 2, "s"), ConfigError);
  EXPECT_THROW(ParseVectorLaw(YAML::Load("{type: linear, stiffness: [[1, 2]]}"), 2, "s"),
               ConfigError);
}

}  // namespace
}  // namespace hybridtest::constitutive
