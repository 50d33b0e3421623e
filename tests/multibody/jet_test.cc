// Jet<T> arithmetic against central finite differences. For an expression φ(q, t) evaluated on
// jets seeded with q_k(s) = q0_k + q̇_k s + ½ q̈_k s² and t(s) = t0 + s, the jet must carry
//   v = φ,  d1 = dφ/ds,  d2 = d²φ/ds²  (at s = 0),  dq_k = ∂φ/∂q_k.
#include "hybridtest/multibody/jet.h"
#include "hybridtest/multibody/scalar.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace hybridtest::multibody {
namespace {

using J = Jet<double>;

// Each expression is written once, generically, so that the same code runs on doubles (for
// the finite differences) and on jets (under test).
struct Expression {
  std::string name;
  std::function<double(double, double, double)> on_double;
  std::function<J(const J&, const J&, const J&)> on_jet;
};

#define HYBRIDTEST_EXPRESSION(name, body)                                        \
  Expression {                                                                   \
    name, [](double q0, double q1, [[maybe_unused]] double t) { using std::cos; using std::exp;   \
                                               using std::log; using std::pow;   \
                                               using std::sin; using std::sqrt;  \
                                               using std::tan; return body; },   \
        [](const J& q0, const J& q1, [[maybe_unused]] const J& t) { return J(body); }             \
  }

std::vector<Expression> Expressions() {
  return {
      HYBRIDTEST_EXPRESSION("sin·cos + t·q", sin(q0) * cos(q1) + t * q0),
      HYBRIDTEST_EXPRESSION("exp(q t) / (2 + cos q)", exp(q0 * t) / (2.0 + cos(q1))),
      HYBRIDTEST_EXPRESSION("log · sqrt", log(2.0 + q0 * q0) * sqrt(1.5 + sin(q1 * t))),
      HYBRIDTEST_EXPRESSION("pow − c / (1 + q²)",
                            pow(1.2 + q0 * q1, 2.5) - 3.0 / (1.0 + q1 * q1)),
      HYBRIDTEST_EXPRESSION("tan", tan(0.3 * q0 + 0.1 * t) - q1 / 4.0),
      HYBRIDTEST_EXPRESSION("chain sin(exp(cos))", sin(exp(cos(q0 + t)) * q1)),
      HYBRIDTEST_EXPRESSION("quotient of products", (q0 * q1 * t - 1.0) / (q0 * q0 + t * t + 0.5)),
      HYBRIDTEST_EXPRESSION("nested sqrt/pow", sqrt(pow(1.0 + q0 * q0, 1.5) + 2.0 - q1) * -q0),
  };
}
#undef HYBRIDTEST_EXPRESSION

struct Motion {
  std::array<double, 2> q0, qd, qdd;
  double t0;
  std::array<double, 2> At(double s) const {
    return {q0[0] + qd[0] * s + 0.5 * qdd[0] * s * s, q0[1] + qd[1] * s + 0.5 * qdd[1] * s * s};
  }
};

J Seed(double v, double d1, double d2, int k) {
  J j;
  j.v = v;
  j.d1 = d1;
  j.d2 = d2;
  j.n = 2;
  j.dq[0] = k == 0 ? 1.0 : 0.0;
  j.dq[1] = k == 1 ? 1.0 : 0.0;
  return j;
}

TEST(JetTest, MatchesCentralFiniteDifferences) {
  const std::vector<Motion> motions = {
      {{0.3, -0.7}, {1.1, 0.4}, {-0.5, 2.0}, 0.8},
      {{-1.2, 0.9}, {-0.3, -1.6}, {0.0, 0.0}, 1.7},
      {{0.05, 0.2}, {2.5, 0.1}, {1.3, -0.9}, 0.2},
  };
  for (const Expression& e : Expressions()) {
    for (std::size_t m = 0; m < motions.size(); ++m) {
      const Motion& mo = motions[m];
      J time;
      time.v = mo.t0;
      time.d1 = 1.0;
      const J jet = e.on_jet(Seed(mo.q0[0], mo.qd[0], mo.qdd[0], 0),
                             Seed(mo.q0[1], mo.qd[1], mo.qdd[1], 1), time);
      auto phi = [&](double s) {
        const auto q = mo.At(s);
        return e.on_double(q[0], q[1], mo.t0 + s);
      };
      const std::string what = e.name + ", motion " + std::to_string(m);
      const double f0 = phi(0.0);
      const double scale = std::max(1.0, std::abs(f0));
      EXPECT_NEAR(jet.v, f0, 1e-14 * scale) << what;
      // d1: central difference, O(h²).
      const double h1 = 1e-5;
      EXPECT_NEAR(jet.d1, (phi(h1) - phi(-h1)) / (2 * h1), 1e-7 * scale) << what;
      // d2: second central difference, O(h²) with round-off O(ε/h²).
      const double h2 = 1e-3;
      const double d2_scale = std::max(scale, std::abs(jet.d2));
      EXPECT_NEAR(jet.d2, (phi(h2) - 2 * f0 + phi(-h2)) / (h2 * h2), 1e-4 * d2_scale) << what;
      // dq_k: partial derivatives at fixed t.
      ASSERT_EQ(jet.n, 2) << what;
      for (int k = 0; k < 2; ++k) {
        std::array<double, 2> qp = mo.q0, qm = mo.q0;
        qp[k] += h1;
        qm[k] -= h1;
        const double fd = (e.on_double(qp[0], qp[1], mo.t0) - e.on_double(qm[0], qm[1], mo.t0)) /
                          (2 * h1);
        EXPECT_NEAR(jet.dq[k], fd, 1e-7 * scale) << what << ", dq" << k;
      }
    }
  }
}

// Negative control: a jet that ignores q̈ in d2 would be caught, because the seeds' q̈ enter d2
// through φ' q̈ (here φ = q0², d2 = 2 q̇² + 2 q0 q̈).
TEST(JetTest, SecondDerivativeUsesTheSeedsAcceleration) {
  const J q = Seed(0.7, 1.5, -3.0, 0);
  const J sq = q * q;
  EXPECT_DOUBLE_EQ(sq.d2, 2 * 1.5 * 1.5 + 2 * 0.7 * -3.0);
  EXPECT_DOUBLE_EQ(sq.dq[0], 1.4);
  EXPECT_EQ(sq.dq[1], 0.0);
}

// Constants convert implicitly and carry no derivatives; a jet with fewer active entries
// combines with a longer one entry by entry.
TEST(JetTest, ConstantsAndShorterJetsCombine) {
  const J c(2.5);
  EXPECT_EQ(c.n, 0);
  EXPECT_EQ(c.d1, 0.0);
  const J q = Seed(0.3, 1.0, 0.0, 1);
  const J s = c * q + 1.0;
  EXPECT_EQ(s.n, 2);
  EXPECT_DOUBLE_EQ(s.v, 1.75);
  EXPECT_DOUBLE_EQ(s.dq[1], 2.5);
  EXPECT_DOUBLE_EQ(s.d1, 2.5);
}

// x² at x = 0 on Jet<AutoDiff> (a model file's `^2` in a Jacobian, e.g. the benchmark
// bicycle's contact point): the derivatives are finite, pow(v, 0)'s own derivative is not used.
TEST(JetTest, SquareAtZeroHasFiniteAutoDiffDerivatives) {
  Jet<AutoDiff> x;
  x.v = AutoDiff(0.0, Derivatives::Unit(1, 0));
  x.d1 = AutoDiff(0.5, Derivatives::Zero(1));
  x.d2 = AutoDiff(0.0, Derivatives::Zero(1));
  x.n = 1;
  x.dq[0] = AutoDiff(1.0, Derivatives::Zero(1));
  const Jet<AutoDiff> y = pow(x, 2.0);
  EXPECT_EQ(y.v.value(), 0.0);
  EXPECT_TRUE(std::isfinite(y.d1.derivatives()(0)));
  EXPECT_DOUBLE_EQ(y.d1.derivatives()(0), 1.0);   // d(2 x ẋ)/dx = 2 ẋ
  EXPECT_DOUBLE_EQ(y.d2.value(), 0.5);            // 2 ẋ² + 2 x ẍ
  EXPECT_TRUE(std::isfinite(y.d2.derivatives()(0)));
}

}  // namespace
}  // namespace hybridtest::multibody
