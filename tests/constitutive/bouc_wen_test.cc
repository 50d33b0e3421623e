#include "hybridtest/constitutive/bouc_wen.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::constitutive {
namespace {

constexpr double kK0 = 5000.0;   // [N/m]
constexpr double kAlpha = 0.1;
constexpr double kYield = 0.002;  // [m]

BoucWen MakeLaw(double n = 1.0) {
  return BoucWen(BoucWen::FromYieldDisplacement(kK0, kAlpha, kYield, n));
}

// Drives the law along `path` (trial + commit at each point) and returns the forces.
std::vector<double> Drive(RestoringForceLaw& law, const std::vector<double>& path) {
  std::vector<double> forces;
  for (double x : path) {
    forces.push_back(law.Trial(x));
    law.Commit();
  }
  return forces;
}

std::vector<double> Cycle(double amplitude, int points_per_cycle, int cycles) {
  std::vector<double> path;
  for (int i = 1; i <= points_per_cycle * cycles; ++i) {
    path.push_back(amplitude * std::sin(2.0 * std::numbers::pi * i / points_per_cycle));
  }
  return path;
}

TEST(BoucWen, TangentAtOriginIsInitialStiffness) {
  for (double n : {1.0, 2.0}) {
    BoucWen law = MakeLaw(n);
    const double h = 1e-7;
    const double slope = (law.Trial(h) - law.Trial(-h)) / (2 * h);
    EXPECT_NEAR(slope, kK0, 1e-3 * kK0) << "n=" << n;
  }
}

TEST(BoucWen, ClassicFormTangentIsK0TimesAlphaPlusOneMinusAlphaA) {
  BoucWen::Parameters p;
  p.initial_stiffness = kK0;
  p.alpha = 0.2;
  p.a = 0.5;
  p.beta = 300.0;
  p.gamma = 200.0;
  BoucWen law(p);
  const double h = 1e-8;
  EXPECT_NEAR(law.Trial(h) / h, kK0 * (0.2 + 0.8 * 0.5), 1e-3 * kK0);
  EXPECT_NEAR(law.ultimate_z(), 0.5 / 500.0, 1e-15);
}

TEST(BoucWen, LargeAmplitudeApproachesPostYieldAsymptote) {
  BoucWen law = MakeLaw();
  // Monotonic loading to 20 x_y, in many small committed steps.
  std::vector<double> up;
  for (int i = 1; i <= 400; ++i) up.push_back(20 * kYield * i / 400.0);
  const double f_up = Drive(law, up).back();
  const double x = 20 * kYield;
  EXPECT_NEAR(f_up, kAlpha * kK0 * x + (1 - kAlpha) * kK0 * kYield, 1e-6 * kK0 * kYield);
  // Reverse to -20 x_y: the plateau changes sign.
  std::vector<double> down;
  for (int i = 1; i <= 800; ++i) down.push_back(x - 2 * x * i / 800.0);
  const double f_down = Drive(law, down).back();
  EXPECT_NEAR(f_down, -kAlpha * kK0 * x - (1 - kAlpha) * kK0 * kYield, 1e-6 * kK0 * kYield);
}

TEST(BoucWen, ClosedLoopDissipatesPositiveEnergy) {
  BoucWen law = MakeLaw();
  const double amplitude = 3 * kYield;
  const int points = 2000;
  Drive(law, Cycle(amplitude, points, 1));  // first cycle: leave the virgin curve
  const auto path = Cycle(amplitude, points, 1);
  const auto forces = Drive(law, path);
  double energy = 0.0;
  double x_prev = path.back(), f_prev = forces.back();  // the cycle is closed
  for (std::size_t i = 0; i < path.size(); ++i) {
    energy += 0.5 * (forces[i] + f_prev) * (path[i] - x_prev);
    x_prev = path[i];
    f_prev = forces[i];
  }
  EXPECT_GT(energy, 0.0);
  // Bounded by the rigid-plastic rectangle of the hysteretic part: 4 (1-α) k0 x_y · A_x.
  EXPECT_LT(energy, 4 * (1 - kAlpha) * kK0 * kYield * amplitude);
  // A linear spring would dissipate nothing: the loop really is hysteretic (not round-off).
  EXPECT_GT(energy, 0.1 * (1 - kAlpha) * kK0 * kYield * amplitude);
}

TEST(BoucWen, TrialWithoutCommitDoesNotChangeState) {
  BoucWen law = MakeLaw();
  Drive(law, {0.001, 0.003});
  const double z = law.committed_z();
  const double reference = law.Trial(0.0025);
  law.Trial(-0.01);  // a wild trial, never committed
  law.Trial(0.02);
  EXPECT_EQ(law.committed_z(), z);
  EXPECT_EQ(law.committed_displacement(), 0.003);
  EXPECT_EQ(law.Trial(0.0025), reference);
}

TEST(BoucWen, LargeTrialIncrementMatchesManySmallCommittedSteps) {
  // Sub-stepping: one trial jump from 0 to 4 x_y equals walking there in 1000 committed steps.
  BoucWen jump = MakeLaw(2.0);
  BoucWen walk = MakeLaw(2.0);
  std::vector<double> path;
  for (int i = 1; i <= 1000; ++i) path.push_back(4 * kYield * i / 1000.0);
  const double f_walk = Drive(walk, path).back();
  const double f_jump = jump.Trial(4 * kYield);
  EXPECT_NEAR(f_jump, f_walk, 1e-8 * kK0 * kYield);
}

TEST(BoucWen, CloneCopiesCommittedState) {
  BoucWen law = MakeLaw();
  Drive(law, {0.001, 0.004});
  auto copy = law.Clone();
  EXPECT_EQ(copy->Trial(0.002), law.Trial(0.002));
}

TEST(BoucWen, RejectsBadParameters) {
  EXPECT_THROW(MakeLaw(0.5), ConfigError);
  EXPECT_THROW(BoucWen(BoucWen::FromYieldDisplacement(-1.0, 0.1, kYield)), ConfigError);
  EXPECT_THROW(BoucWen(BoucWen::FromYieldDisplacement(kK0, 1.5, kYield)), ConfigError);
  EXPECT_THROW(BoucWen::FromYieldDisplacement(kK0, 0.1, 0.0), ConfigError);
  BoucWen::Parameters p;
  p.initial_stiffness = kK0;
  p.beta = -1.0;
  p.gamma = 0.5;
  EXPECT_THROW(BoucWen{p}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::constitutive
