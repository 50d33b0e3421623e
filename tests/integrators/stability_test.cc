// Linear stability of explicit Runge–Kutta schemes (stability.h), cross-checked against the
// stepper itself: one ExplicitRungeKutta step of y' = λy multiplies y by R(hλ).
#include "hybridtest/integrators/stability.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"

namespace hybridtest::integrators {
namespace {

TEST(Stability, PolynomialCoefficientsAreOneOverKFactorialUpToTheOrder) {
  for (const ButcherTableau& t : Catalogue()) {
    const Eigen::VectorXd beta = StabilityPolynomial(t);
    ASSERT_EQ(beta.size(), t.stages() + 1) << t.name;
    double factorial = 1.0;
    for (int k = 0; k <= t.order; ++k) {
      if (k > 0) factorial *= k;
      EXPECT_NEAR(beta(k), 1.0 / factorial, 1e-12) << t.name << " k=" << k;
    }
  }
}

// Oracle: the stepper applied to y' = λy written as a real 2-vector [Re y, Im y].
TEST(Stability, PolynomialMatchesOneStepOfTheStepper) {
  const std::complex<double> z(-0.7, 1.3);
  for (const ButcherTableau& t : Catalogue()) {
    ExplicitRungeKutta stepper(t, 2);
    const Eigen::VectorXd x = Eigen::Vector2d(1.0, 0.0);
    Eigen::VectorXd next(2);
    stepper.Step(0.0, 1.0, x, [&](int, double, const Eigen::VectorXd& xi,
                                  Eigen::Ref<Eigen::VectorXd> k) {
      const std::complex<double> y(xi(0), xi(1));
      const std::complex<double> dy = z * y;
      k(0) = dy.real();
      k(1) = dy.imag();
    }, next);
    const std::complex<double> r = EvalStabilityPolynomial(StabilityPolynomial(t), z);
    EXPECT_NEAR(next(0), r.real(), 1e-12) << t.name;
    EXPECT_NEAR(next(1), r.imag(), 1e-12) << t.name;
  }
}

TEST(Stability, KnownRealAxisLimits) {
  // Forward Euler, Heun: |1 + z| ≤ 1 and |1 + z + z²/2| ≤ 1 end at z = −2; RK4 at −2.7853.
  const std::complex<double> lambda(-100.0, 0.0);
  EXPECT_NEAR(LargestStableStep(StabilityPolynomial(FindTableau("heun")), lambda), 0.02, 1e-8);
  EXPECT_NEAR(LargestStableStep(StabilityPolynomial(FindTableau("rk4")), lambda) * 100.0,
              2.785293563, 1e-6);
}

TEST(Stability, RK4CoversTheImaginaryAxisUpToTwoRootTwo) {
  // |R(iy)| = 1 exactly at y = 2√2 for RK4, and stays ≤ 1 (to 1e-6) below it.
  const double h = LargestStableStep(StabilityPolynomial(FindTableau("rk4")), {0.0, 1.0});
  EXPECT_NEAR(h, 2.0 * std::sqrt(2.0), 1e-3);
}

TEST(Stability, TheSmallestLimitOverAllModesIsReportedWithItsMode) {
  std::complex<double> limiting;
  const double h = LargestStableStep(FindTableau("heun"),
                                     {{-10.0, 0.0}, {-1000.0, 0.0}, {0.0, 0.0}}, &limiting);
  EXPECT_NEAR(h, 2e-3, 1e-8);  // the 1e-6 growth tolerance moves it by ~1e-9 s
  EXPECT_EQ(limiting, std::complex<double>(-1000.0, 0.0));
  EXPECT_TRUE(std::isinf(LargestStableStep(FindTableau("heun"), {{0.0, 0.0}})));
}

TEST(Stability, LightlyDampedModeIsLimitedWhereHeunStartsToAmplify) {
  // λ = ω(−ζ + i√(1−ζ²)): heun's |R| exceeds 1 near hω ≈ (8ζ)^{1/3} for small ζ.
  const double omega = 100.0, zeta = 0.01;
  const std::complex<double> lambda(-zeta * omega, omega * std::sqrt(1 - zeta * zeta));
  const Eigen::VectorXd beta = StabilityPolynomial(FindTableau("heun"));
  const double h = LargestStableStep(beta, lambda);
  EXPECT_NEAR(h * omega, std::cbrt(8.0 * zeta), 0.02);
  EXPECT_LE(std::abs(EvalStabilityPolynomial(beta, 0.99 * h * lambda)), 1.0 + 1e-6);
  EXPECT_GT(std::abs(EvalStabilityPolynomial(beta, 1.01 * h * lambda)), 1.0 + 1e-6);
}

}  // namespace
}  // namespace hybridtest::integrators
