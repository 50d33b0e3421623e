// Model-file expressions: precedence and functions against hand-computed values; the same
// expression evaluated on double, AutoDiff and Jet agrees, and the jet's derivatives match
// central differences; affine forms are found where they exist; errors name the token and
// suggest close names.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hybridtest/modelfile/compiled_scalar.h"

namespace hybridtest::modelfile {
namespace {

using multibody::AutoDiff;
using multibody::Derivatives;
using multibody::Jet;

SymbolTable Symbols() {
  SymbolTable s;
  s.Add({"t", Op::kTime, -1, 0.0});
  s.Add({"q1", Op::kCoordinate, 0, 0.0});
  s.Add({"q2", Op::kCoordinate, 1, 0.0});
  s.Add({"u1", Op::kSpeed, 0, 0.0});
  s.Add({"r1", Op::kSlot, 0, 0.0});
  s.Add({"ramp", Op::kTimeFunction, 0, 0.0});
  s.Add({"l_b", Op::kConst, -1, 0.5});
  s.Add({"m_b", Op::kConst, -1, 2.0});
  return s;
}

double Eval(const std::string& text, double t, double q1, double q2) {
  const Expression e = Expression::Parse(text, Symbols());
  const double q[2] = {q1, q2}, u[1] = {0.3}, r[1] = {7.0}, tf[1] = {0.25};
  return Evaluate(e, Variables<double>{t, q, u, r, tf});
}

TEST(ExpressionTest, PrecedenceAssociativityAndFunctions) {
  EXPECT_DOUBLE_EQ(Eval("1 + 2 * 3", 0, 0, 0), 7.0);
  EXPECT_DOUBLE_EQ(Eval("(1 + 2) * 3", 0, 0, 0), 9.0);
  EXPECT_DOUBLE_EQ(Eval("2 ^ 3 ^ 2", 0, 0, 0), 512.0);  // right-associative
  EXPECT_DOUBLE_EQ(Eval("2 ** 3", 0, 0, 0), 8.0);
  EXPECT_DOUBLE_EQ(Eval("-2 ^ 2", 0, 0, 0), -4.0);  // unary minus binds looser than ^
  EXPECT_DOUBLE_EQ(Eval("8 / 4 / 2", 0, 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(Eval("10 - 4 - 3", 0, 0, 0), 3.0);
  EXPECT_DOUBLE_EQ(Eval("1.5e3 * l_b", 0, 0, 0), 750.0);
  EXPECT_DOUBLE_EQ(Eval("sin(q1) + cos(q2)", 0, 0.4, 1.1), std::sin(0.4) + std::cos(1.1));
  EXPECT_DOUBLE_EQ(Eval("tan(q1) * exp(t) - log(q2) + sqrt(m_b)", 0.2, 0.4, 1.1),
                   std::tan(0.4) * std::exp(0.2) - std::log(1.1) + std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(Eval("abs(q1) + min(q1, q2) + max(q1, q2) + pow(q2, q1)", 0, -0.4, 1.1),
                   0.4 - 0.4 + 1.1 + std::pow(1.1, -0.4));
  EXPECT_DOUBLE_EQ(Eval("(1 - exp(-t / 0.5)) * 100", 0.3, 0, 0), (1 - std::exp(-0.6)) * 100);
  EXPECT_DOUBLE_EQ(Eval("-(r1 + 2 * u1) + ramp * 100", 0, 0, 0), -(7.0 + 0.6) + 25.0);
  EXPECT_DOUBLE_EQ(Eval("2 * pi", 0, 0, 0), 2 * std::numbers::pi);
}

TEST(ExpressionTest, ConstantsFoldAndAffineFormsAreFound) {
  EXPECT_TRUE(Expression::Parse("2 * pi / 3 + sqrt(m_b)", Symbols()).is_constant());
  const LinearForm f = Linearize(Expression::Parse("-(r1 + l_b * m_b * u1) + 3 * q2 / 2 + 1", Symbols()));
  ASSERT_TRUE(f.affine);
  EXPECT_DOUBLE_EQ(f.constant, 1.0);
  ASSERT_EQ(f.terms.size(), 3u);
  EXPECT_FALSE(Linearize(Expression::Parse("q1 * q2", Symbols())).affine);
  EXPECT_FALSE(Linearize(Expression::Parse("sin(q1)", Symbols())).affine);
}

TEST(ExpressionTest, JetsAndAutoDiffAgreeWithDoubleAndFiniteDifferences) {
  const Expression e = Expression::Parse(
      "l_b * sin(q1) * cos(q2) + pow(q2, 3) / (2 + q1 ^ 2) + abs(q1 - q2) + max(q1, t) * exp(-t)",
      Symbols());
  const double q[2] = {0.7, -0.2}, qd[2] = {0.9, 1.3}, t = 0.4;
  auto value = [&](double s) {  // along the motion q(s) = q + s q̇, t + s
    const double qs[2] = {q[0] + s * qd[0], q[1] + s * qd[1]};
    return Evaluate(e, Variables<double>{t + s, qs, {}, {}, {}});
  };
  // Jet<double> seeded with q̇ (q̈ = 0) and ṫ = 1.
  Jet<double> jq[2], jt;
  for (int k = 0; k < 2; ++k) {
    jq[k].v = q[k];
    jq[k].d1 = qd[k];
    jq[k].n = 2;
    jq[k].dq[k] = 1.0;
  }
  jt.v = t;
  jt.d1 = 1.0;
  const Jet<double> j = Evaluate(e, Variables<Jet<double>>{jt, jq, {}, {}, {}});
  const double h = 1e-4;
  EXPECT_NEAR(j.v, value(0.0), 1e-15);
  EXPECT_NEAR(j.d1, (value(h) - value(-h)) / (2 * h), 1e-7);
  EXPECT_NEAR(j.d2, (value(h) - 2 * value(0.0) + value(-h)) / (h * h), 1e-5);
  // AutoDiff: ∂/∂q1 equals the jet's.
  const AutoDiff aq[2] = {AutoDiff(q[0], Derivatives::Unit(2, 0)), AutoDiff(q[1], Derivatives::Unit(2, 1))};
  const AutoDiff a = Evaluate(e, Variables<AutoDiff>{AutoDiff(t, Derivatives::Zero(2)), aq, {}, {}, {}});
  EXPECT_NEAR(a.value(), j.v, 1e-15);
  EXPECT_NEAR(a.derivatives()(0), j.dq[0], 1e-14);
  EXPECT_NEAR(a.derivatives()(1), j.dq[1], 1e-14);
}

std::string ErrorOf(const std::string& text) {
  try {
    Expression::Parse(text, Symbols());
  } catch (const ExpressionError& e) {
    return e.token + " @" + std::to_string(e.column) + ": " + e.message;
  }
  return "no error";
}

TEST(ExpressionTest, ErrorsNameTheTokenAndTheFix) {
  EXPECT_EQ(ErrorOf("l_b * sin(q1").substr(0, 7), "sin @6:");
  EXPECT_NE(ErrorOf("l_b * sin(q1").find("close it with ')'"), std::string::npos);
  const std::string unknown = ErrorOf("2 * m_bb");
  EXPECT_EQ(unknown.substr(0, 8), "m_bb @4:");
  EXPECT_NE(unknown.find("did you mean m_b"), std::string::npos) << unknown;
  EXPECT_NE(ErrorOf("sinh(q1)").find("unknown function"), std::string::npos);
  EXPECT_NE(ErrorOf("pow(q1)").find("two arguments"), std::string::npos);
  EXPECT_NE(ErrorOf("q1 q2").find("missing operator"), std::string::npos);
  EXPECT_NE(ErrorOf("").find("empty"), std::string::npos);
  EXPECT_NE(ErrorOf("1 +").find("ends early"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::modelfile
