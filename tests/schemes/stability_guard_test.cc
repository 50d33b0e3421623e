// The stability guard of the operator-splitting schemes (stability_guard.h): the tangent
// stiffness it estimates from samples, its bound against the oscillator's closed form
// ω_Δ² = (K − K0) / m, its reaction to a growing error estimate (and not to a noisy one), and
// α-OS and MR-OS with a K0 four times too soft and a loose tolerance: every step inside the
// bound and a bounded response.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/schemes/stability_guard.h"
#include "schemes/oscillator.h"

namespace hybridtest::schemes {
namespace {

using testing::CollectRows;
using testing::Oscillator;
using testing::SpringSeam;

constexpr double kInf = std::numeric_limits<double>::infinity();

// The guard after samples of the oscillator's spring along a sine, its modes at rest.
StabilityGuard SampledGuard(const Oscillator& o, double constant) {
  const multibody::Model model = OscillatorModel(o);
  multibody::Data<double> data(model);
  StabilityGuard guard(1, 1, constant);
  Eigen::VectorXd d(1), r(1);
  for (int j = 0; j < 12; ++j) {
    d(0) = 0.01 * std::sin(0.4 * j);
    r(0) = o.k * d(0);
    guard.AddSample(d, r);
  }
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  guard.UpdateModes(model, data, 0.0, x, Eigen::VectorXd::Zero(1),
                    Eigen::VectorXd::Constant(1, 0.5 * o.k));
  return guard;
}

TEST(StabilityGuard, BoundsTheStepByTheStiffnessTheK0DoesNotExplain) {
  Oscillator o;
  o.c = 0.0;  // undamped: the closed form is exact
  for (const double c : {kMrOsStabilityConstant, kAlphaOsStabilityConstant}) {
    StabilityGuard guard = SampledGuard(o, c);
    EXPECT_NEAR(guard.tangent_stiffness(0), o.k, 1e-9 * o.k);
    EXPECT_NEAR(guard.tangent_stiffness_error(0), 0.0, 1e-6 * o.k);
    for (const double k0 : {0.25 * o.k, 0.5 * o.k, 0.9 * o.k}) {
      const double omega_delta = std::sqrt((o.k - k0) / o.m);
      EXPECT_NEAR(guard.StableStep(Eigen::VectorXd::Constant(1, k0)),
                  kStabilityMargin * c / omega_delta, 1e-3 * c / omega_delta)
          << "K0 = " << k0;
    }
    // A K0 at or above the specimen's stiffness: unconditionally stable, no bound.
    EXPECT_EQ(guard.StableStep(Eigen::VectorXd::Constant(1, o.k)), kInf);
    EXPECT_EQ(guard.StableStep(Eigen::VectorXd::Constant(1, 2.0 * o.k)), kInf);
  }
}

TEST(StabilityGuard, NoisySamplesDoNotShortenTheStepsOfARightK0) {
  // Force noise of ±0.5 N on increments of a few mm of an 800 N/m spring.
  const Oscillator o;
  const multibody::Model model = OscillatorModel(o);
  multibody::Data<double> data(model);
  StabilityGuard guard(1, 1, kMrOsStabilityConstant);
  Eigen::VectorXd d(1), r(1);
  for (int j = 0; j < 40; ++j) {
    d(0) = 0.01 * std::sin(0.4 * j);
    r(0) = o.k * d(0) + (j % 2 == 0 ? 0.5 : -0.5);
    guard.AddSample(d, r);
  }
  guard.UpdateModes(model, data, 0.0, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(1),
                    Eigen::VectorXd::Constant(1, o.k));
  EXPECT_GT(guard.tangent_stiffness_error(0), 0.0);
  EXPECT_EQ(guard.StableStep(Eigen::VectorXd::Constant(1, o.k)), kInf);
  EXPECT_EQ(guard.Limit(0.1, 0.05, 1e-3, Eigen::VectorXd::Constant(1, o.k)), 0.1);
}

TEST(StabilityGuard, HalvesAndHoldsTheStepAfterAGrowingErrorOnly) {
  const Eigen::VectorXd k0 = Eigen::VectorXd::Constant(1, 1.0);
  const double tol = 1e-6;
  {
    // Large but not growing three times in a row (what noise does): no reaction.
    StabilityGuard guard(1, 1, kMrOsStabilityConstant);
    for (const double e : {3e-6, 1.5e-6, 5e-6}) guard.AddErrorEstimate(e, 0.02, tol);
    EXPECT_EQ(guard.Limit(0.03, 0.02, 1e-3, k0), 0.03);
  }
  {
    // Growing over steps that did not lengthen, from above twice the tolerance.
    StabilityGuard guard(1, 1, kMrOsStabilityConstant);
    guard.AddErrorEstimate(3e-6, 0.02, tol);
    guard.AddErrorEstimate(4e-6, 0.02, tol);
    guard.AddErrorEstimate(5e-6, 0.015, tol);
    EXPECT_EQ(guard.Limit(0.02, 0.015, 1e-3, k0), 0.0075);
    // Then the step may not grow for kHoldSteps steps, and may afterwards.
    for (int k = 0; k < StabilityGuard::kHoldSteps; ++k) {
      guard.AddErrorEstimate(1e-8, 0.0075, tol);
      EXPECT_EQ(guard.Limit(0.015, 0.0075, 1e-3, k0), 0.0075) << "held step " << k;
    }
    guard.AddErrorEstimate(1e-8, 0.0075, tol);
    EXPECT_EQ(guard.Limit(0.015, 0.0075, 1e-3, k0), 0.015);
    EXPECT_EQ(guard.shortened_steps(), StabilityGuard::kHoldSteps + 1);
  }
}

// α-OS and MR-OS with K0 = K/4 and a tolerance so loose that accuracy alone would let the step
// grow to dt_max = 0.5 s, far past the bound: every step after the first few stays within it
// (with the margin: below c / ω_Δ), and the response stays that of the oscillator.
TEST(StabilityGuard, AdaptiveStepsStayInsideTheBoundWithAK0FourTimesTooSoft) {
  const Oscillator o;
  const multibody::Model model = OscillatorModel(o);
  const double k0 = 0.25 * o.k, duration = 6.0;
  const double omega_delta = std::sqrt((o.k - k0) / o.m);
  for (const SchemeKind kind : {SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
    SchemeConfig c;
    c.kind = kind;
    c.adaptive = {true, 1e-2, 1e-3, 0.5};
    c.substep = 1e-3;
    const double bound = (kind == SchemeKind::kMrOs ? kMrOsStabilityConstant
                                                    : kAlphaOsStabilityConstant) / omega_delta;
    SlotInfo slots{Eigen::VectorXd::Constant(1, k0), Eigen::VectorXd::Constant(1, kInf),
                   Eigen::MatrixXd()};
    auto scheme = MakeScheme(c, integrators::FindTableau("rk4"), 0.01, duration, 600, model, slots);
    SpringSeam seam(o.k);
    CollectRows rows;
    Eigen::VectorXd x0(2), r0(1);
    x0 << 0.01, 0.0;
    seam.Trial({0, 0, 0.0}, x0.head(1), r0);
    scheme->Start(0.0, x0, r0);
    double peak = 0.0, t_last = 0.0, longest = 0.0;
    while (!scheme->finished()) {
      scheme->Step(seam, rows);
      const double t = scheme->committed().t;
      if (scheme->committed().step > 5) longest = std::max(longest, t - t_last);
      t_last = t;
      peak = std::max(peak, std::abs(scheme->committed().x(0)));
    }
    EXPECT_LT(longest, bound) << SchemeKindName(kind);
    EXPECT_GT(longest, 0.5 * bound) << SchemeKindName(kind) << ": the bound is not what limits";
    // Free vibration from 1 cm plus the forced response f0 / k ≈ 6 mm: well below 3 cm.
    EXPECT_LT(peak, 0.03) << SchemeKindName(kind);
  }
}

}  // namespace
}  // namespace hybridtest::schemes
