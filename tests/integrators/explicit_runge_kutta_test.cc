// ExplicitRungeKutta: the stage seam (every stage called once, in order, at the right t_i and
// x_i), the update, aliasing, failure behaviour, and the stability polynomial as an oracle.
#include "hybridtest/integrators/explicit_runge_kutta.h"

#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/integrators/catalogue.h"

namespace hybridtest::integrators {
namespace {

using ::testing::HasSubstr;

// One recorded call of the stage function.
struct StageCall {
  int i;
  double t_i;
  Eigen::VectorXd x_i;
  Eigen::VectorXd k_i;
};

// A linear, non-autonomous test problem x' = J x + g(t), n = 3.
struct LinearProblem {
  Eigen::Matrix3d J;
  LinearProblem() {
    J << -1.0, 2.0, 0.5,  //
        -2.0, -0.3, 1.0,  //
        0.4, -1.0, -0.7;
  }
  Eigen::Vector3d Forcing(double t) const { return {std::sin(t), std::cos(2.0 * t), t}; }
  void Eval(double t, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> k) const {
    k = J * x + Forcing(t);
  }
};

class StepperTest : public ::testing::TestWithParam<std::string> {
 protected:
  const ButcherTableau& tableau() const { return FindTableau(GetParam()); }
};

TEST_P(StepperTest, CallsEveryStageOnceInOrderWithTableauTimesAndStates) {
  const ButcherTableau& tab = tableau();
  const int s = tab.stages();
  const LinearProblem problem;
  ExplicitRungeKutta stepper(tab, 3);
  ASSERT_EQ(stepper.stages(), s);

  const double h = 0.05;
  Eigen::VectorXd x = Eigen::Vector3d(1.0, -0.5, 0.25);
  Eigen::VectorXd x_next(3);
  for (int n = 0; n < 3; ++n) {
    const double t = 0.3 + n * h;
    std::vector<StageCall> calls;
    stepper.Step(t, h, x,
                 [&](int i, double t_i, const Eigen::VectorXd& x_i,
                     Eigen::Ref<Eigen::VectorXd> k_i) {
                   problem.Eval(t_i, x_i, k_i);
                   calls.push_back({i, t_i, x_i, k_i});
                 },
                 x_next);

    // Exactly s calls, i = 0 … s-1 in order (all s stages, not s − 1).
    ASSERT_EQ(static_cast<int>(calls.size()), s) << "step " << n;
    Eigen::VectorXd expected_next = x;
    for (int i = 0; i < s; ++i) {
      EXPECT_EQ(calls[i].i, i);
      EXPECT_DOUBLE_EQ(calls[i].t_i, t + tab.c(i) * h) << "stage " << i;
      // x_i = x + h Σ_{j<i} a_ij k_j, from the recorded k_j.
      Eigen::VectorXd expected_x_i = x;
      for (int j = 0; j < i; ++j) expected_x_i += h * tab.a(i, j) * calls[j].k_i;
      EXPECT_LT((calls[i].x_i - expected_x_i).norm(), 1e-14) << "stage " << i;
      // The stage derivatives are kept, one per column.
      EXPECT_EQ(stepper.stage_derivatives().col(i), calls[i].k_i);
      expected_next += h * tab.b(i) * calls[i].k_i;
    }
    EXPECT_LT((x_next - expected_next).norm(), 1e-14);
    x = x_next;
  }
}

TEST_P(StepperTest, InPlaceStepEqualsOutOfPlaceStep) {
  const LinearProblem problem;
  ExplicitRungeKutta stepper(tableau(), 3);
  auto stage = [&](int, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    problem.Eval(t_i, x_i, k);
  };
  const Eigen::VectorXd x0 = Eigen::Vector3d(0.2, 0.7, -1.1);
  Eigen::VectorXd out(3);
  stepper.Step(1.0, 0.1, x0, stage, out);
  Eigen::VectorXd in_place = x0;
  stepper.Step(1.0, 0.1, in_place, stage, in_place);
  EXPECT_EQ(in_place, out);
  EXPECT_NE(out, x0);
}

// R(z) = 1 + z bᵀ (I − z A)⁻¹ 1, the stability function of the tableau.
std::complex<double> StabilityFunction(const ButcherTableau& tab, std::complex<double> z) {
  const int s = tab.stages();
  const Eigen::MatrixXcd m = Eigen::MatrixXcd::Identity(s, s) - z * tab.a.cast<std::complex<double>>();
  const Eigen::VectorXcd y = m.partialPivLu().solve(Eigen::VectorXcd::Ones(s));
  return 1.0 + z * tab.b.cast<std::complex<double>>().dot(y);
}

TEST_P(StepperTest, ScalarLinearStepIsStabilityFunctionTimesState) {
  const ButcherTableau& tab = tableau();
  ExplicitRungeKutta stepper(tab, 1);
  for (double lambda : {-958.0, -3.0, 0.5}) {
    const double h = 1e-3;
    const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.8);
    Eigen::VectorXd x_next(1);
    stepper.Step(0.0, h, x,
                 [&](int, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                   k = lambda * x_i;
                 },
                 x_next);
    const std::complex<double> r = StabilityFunction(tab, h * lambda);
    EXPECT_NEAR(x_next(0), r.real() * 0.8, 1e-14) << "lambda = " << lambda;
    EXPECT_NEAR(r.imag(), 0.0, 1e-15);
  }
}

TEST_P(StepperTest, RotatingLinearStepIsComplexStabilityFunction) {
  // y' = λ y with λ = α + iω, as the real system [y1; y2]' = [α −ω; ω α] [y1; y2].
  const ButcherTableau& tab = tableau();
  ExplicitRungeKutta stepper(tab, 2);
  const double alpha = -0.7, omega = 4.0, h = 0.2;
  const Eigen::VectorXd x = Eigen::Vector2d(0.6, -0.3);
  Eigen::VectorXd x_next(2);
  stepper.Step(0.0, h, x,
               [&](int, double, const Eigen::VectorXd& y, Eigen::Ref<Eigen::VectorXd> k) {
                 k(0) = alpha * y(0) - omega * y(1);
                 k(1) = omega * y(0) + alpha * y(1);
               },
               x_next);
  const std::complex<double> expected =
      StabilityFunction(tab, h * std::complex<double>(alpha, omega)) *
      std::complex<double>(x(0), x(1));
  EXPECT_NEAR(x_next(0), expected.real(), 1e-14);
  EXPECT_NEAR(x_next(1), expected.imag(), 1e-14);
}

TEST_P(StepperTest, StabilityFunctionIsTruncatedExponentialWhenStagesEqualOrder) {
  // For an explicit method with s = p ≤ 4, R(z) = Σ_{k≤p} z^k / k!: a cross-check of the
  // resolvent formula used above against a closed form.
  const ButcherTableau& tab = tableau();
  if (tab.stages() != tab.order) GTEST_SKIP() << "s != p";
  for (double z : {-2.5, -0.4, 0.3}) {
    double series = 0.0, term = 1.0;
    for (int k = 0; k <= tab.order; ++k) {
      series += term;
      term *= z / (k + 1);
    }
    EXPECT_NEAR(StabilityFunction(tab, z).real(), series, 1e-13) << "z = " << z;
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, StepperTest, ::testing::ValuesIn(TableauNames()),
                         [](const auto& param_info) { return param_info.param; });

TEST(ExplicitRungeKutta, ConstructorValidatesTableauNamingIt) {
  ButcherTableau bad = FindTableau("heun");
  bad.name = "custom_rk";
  bad.order = 3;
  try {
    ExplicitRungeKutta stepper(bad, 2);
    FAIL() << "accepted a second-order tableau claiming order 3";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("custom_rk"));
    EXPECT_THAT(e.what(), HasSubstr("order-3 condition"));
  }
  EXPECT_THROW(ExplicitRungeKutta(FindTableau("rk4"), 0), ConfigError);
}

TEST(ExplicitRungeKutta, RejectsStateOfWrongSize) {
  ExplicitRungeKutta stepper(FindTableau("rk4"), 3);
  EXPECT_EQ(stepper.state_size(), 3);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2), x_next(3);
  int calls = 0;
  try {
    stepper.Step(0.0, 0.1, x,
                 [&](int, double, const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd> k) {
                   ++calls;
                   k.setZero();
                 },
                 x_next);
    FAIL() << "accepted a state of size 2 for a stepper of size 3";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("x has 2 entries"));
    EXPECT_THAT(e.what(), HasSubstr("state size 3"));
  }
  EXPECT_EQ(calls, 0) << "no trial may run for a step that cannot complete";
}

TEST(ExplicitRungeKutta, ThrowingStageLeavesOutputUntouched) {
  ExplicitRungeKutta stepper(FindTableau("rk4"), 2);
  const Eigen::VectorXd x = Eigen::Vector2d(1.0, 2.0);
  Eigen::VectorXd x_next = Eigen::Vector2d(7.0, 8.0);
  std::vector<int> called;
  auto failing = [&](int i, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    called.push_back(i);
    if (i == 2) throw std::runtime_error("bench lost");
    k = -x_i;
  };
  EXPECT_THROW(stepper.Step(0.0, 0.1, x, failing, x_next), std::runtime_error);
  EXPECT_THAT(called, ::testing::ElementsAre(0, 1, 2));
  EXPECT_EQ(x_next, Eigen::Vector2d(7.0, 8.0));
}

TEST(ExplicitRungeKutta, UnwrittenStageDerivativePoisonsTheStep) {
  ExplicitRungeKutta stepper(FindTableau("heun"), 2);
  const Eigen::VectorXd x = Eigen::Vector2d(1.0, 2.0);
  Eigen::VectorXd x_next(2);
  // First step writes everything; second forgets k(1) at stage 1, which must not silently reuse
  // the value left from the first step.
  auto full = [](int, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    k = -x_i;
  };
  stepper.Step(0.0, 0.1, x, full, x_next);
  ASSERT_TRUE(x_next.allFinite());
  auto forgetful = [](int i, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    k(0) = -x_i(0);
    if (i == 0) k(1) = -x_i(1);
  };
  stepper.Step(0.0, 0.1, x, forgetful, x_next);
  EXPECT_TRUE(std::isfinite(x_next(0)));
  EXPECT_TRUE(std::isnan(x_next(1)));
}

TEST(ExplicitRungeKutta, ResizesOutputOfWrongSize) {
  ExplicitRungeKutta stepper(FindTableau("euler"), 2);
  const Eigen::VectorXd x = Eigen::Vector2d(1.0, 2.0);
  Eigen::VectorXd x_next;
  stepper.Step(0.0, 0.5, x,
               [](int, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                 k = x_i;
               },
               x_next);
  EXPECT_EQ(x_next, Eigen::Vector2d(1.5, 3.0));
}

}  // namespace
}  // namespace hybridtest::integrators
