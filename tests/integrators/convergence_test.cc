// Order of convergence of every catalogue tableau, table-driven over Catalogue(): a new entry is
// tested by just being added. Each method integrates ODEs with known solutions over a fixed
// interval with h, h/2, h/4, h/8; the observed order log2(e(h) / e(h/2)) must lie within ±0.2
// of the claimed order for each halving.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"

namespace hybridtest::integrators {
namespace {

// An initial-value problem x' = f(t, x) on [0, t_end] with its exact solution.
struct TestProblem {
  std::string name;
  double t_end;
  int coarse_steps;  // number of steps for the coarsest h
  std::function<void(double, const Eigen::VectorXd&, Eigen::Ref<Eigen::VectorXd>)> rhs;
  std::function<Eigen::VectorXd(double)> exact;
};

// y' = -2 t y², y(0) = 1: y = 1 / (1 + t²). Scalar, nonlinear, non-autonomous (tests c).
TestProblem Riccati() {
  return {"riccati", 2.0, 32,
          [](double t, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> k) {
            k(0) = -2.0 * t * x(0) * x(0);
          },
          [](double t) { return Eigen::VectorXd::Constant(1, 1.0 / (1.0 + t * t)); }};
}

// A limit cycle: in polar form r' = r (1 − r²), θ' = 1, so r = 1 / sqrt(1 + (1/r0² − 1) e^{−2t}),
// θ = t. Two-dimensional, nonlinear and rotating. r0 = 0.5, θ0 = 0.
TestProblem LimitCycle() {
  return {"limit_cycle", 2.0, 32,
          [](double, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> k) {
            const double growth = 1.0 - x.squaredNorm();
            k(0) = growth * x(0) - x(1);
            k(1) = growth * x(1) + x(0);
          },
          [](double t) {
            const double r0 = 0.5;
            const double r = 1.0 / std::sqrt(1.0 + (1.0 / (r0 * r0) - 1.0) * std::exp(-2.0 * t));
            return Eigen::Vector2d(r * std::cos(t), r * std::sin(t)).eval();
          }};
}

// Max-norm error at t_end after `steps` fixed steps.
double FinalError(const ButcherTableau& tableau, const TestProblem& problem, int steps) {
  const Eigen::VectorXd x0 = problem.exact(0.0);
  ExplicitRungeKutta stepper(tableau, static_cast<int>(x0.size()));
  const double h = problem.t_end / steps;
  Eigen::VectorXd x = x0;
  for (int n = 0; n < steps; ++n) {
    stepper.Step(n * h, h, x,
                 [&](int, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
                   problem.rhs(t_i, x_i, k);
                 },
                 x);
  }
  return (x - problem.exact(problem.t_end)).lpNorm<Eigen::Infinity>();
}

// Observed orders log2(e(h) / e(h/2)) for h, h/2, h/4, h/8; also checks that the finest error
// is far above round-off, where the ratio would mean nothing.
std::vector<double> ObservedOrders(const ButcherTableau& tableau, const TestProblem& problem) {
  std::vector<double> errors;
  for (int refinement = 0; refinement < 4; ++refinement) {
    errors.push_back(FinalError(tableau, problem, problem.coarse_steps << refinement));
  }
  EXPECT_GT(errors.back(), 1e-13) << tableau.name << " on " << problem.name
                                  << ": error at round-off level; use a coarser h";
  std::vector<double> orders;
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    orders.push_back(std::log2(errors[i] / errors[i + 1]));
  }
  return orders;
}

class ConvergenceTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ConvergenceTest, ObservedOrderMatchesClaimedOrder) {
  const ButcherTableau& tableau = FindTableau(GetParam());
  for (const TestProblem& problem : {Riccati(), LimitCycle()}) {
    const std::vector<double> orders = ObservedOrders(tableau, problem);
    for (std::size_t i = 0; i < orders.size(); ++i) {
      EXPECT_NEAR(orders[i], tableau.order, 0.2)
          << tableau.name << " on " << problem.name << ", halving " << i;
    }
  }
}

// Negative control: the measurement is sharp enough to tell orders apart, so a catalogue entry
// that under-claims (a third-order method listed as second order) would fail the test above.
TEST(Convergence, DistinguishesNeighbouringOrders) {
  ButcherTableau under_claimed = FindTableau("rk3");
  under_claimed.order = 2;
  for (const TestProblem& problem : {Riccati(), LimitCycle()}) {
    for (double observed : ObservedOrders(under_claimed, problem)) {
      EXPECT_GT(std::abs(observed - under_claimed.order), 0.5) << problem.name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, ConvergenceTest, ::testing::ValuesIn(TableauNames()),
                         [](const auto& param_info) { return param_info.param; });

}  // namespace
}  // namespace hybridtest::integrators
