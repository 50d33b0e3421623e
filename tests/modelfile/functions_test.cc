// The functions added for turbine models (atan2 tanh asin acos atan sign, if with comparisons,
// units after numbers) and the parser's depth limit: values against <cmath>, and on AutoDiff,
// Jet<double> and Jet<AutoDiff> the derivatives against central differences, so the engine's
// Jacobians and coupling matrix stay exact through them.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>

#include "hybridtest/modelfile/compiled_scalar.h"
#include "hybridtest/modelfile/units.h"

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
  s.Add({"m", Op::kConst, -1, 3.0});
  return s;
}

double Eval(const std::string& text, double q1, double q2, double u1 = 0.0) {
  const Expression e = Expression::Parse(text, Symbols());
  const double q[2] = {q1, q2}, u[1] = {u1}, r[1] = {7.0};
  return Evaluate(e, Variables<double>{0.1, q, u, r, {}});
}

std::string ErrorOf(const std::string& text) {
  try {
    Expression::Parse(text, Symbols());
  } catch (const ExpressionError& e) {
    return e.token + ": " + e.message;
  }
  return "no error";
}

TEST(FunctionsTest, ValuesEqualCmath) {
  EXPECT_DOUBLE_EQ(Eval("atan2(q1, q2)", 0.3, -0.8), std::atan2(0.3, -0.8));
  EXPECT_DOUBLE_EQ(Eval("atan2(q1, q2)", -0.3, -0.8), std::atan2(-0.3, -0.8));  // third quadrant
  EXPECT_DOUBLE_EQ(Eval("tanh(q1)", 0.7, 0), std::tanh(0.7));
  EXPECT_DOUBLE_EQ(Eval("asin(q1)", 0.7, 0), std::asin(0.7));
  EXPECT_DOUBLE_EQ(Eval("acos(q1)", 0.7, 0), std::acos(0.7));
  EXPECT_DOUBLE_EQ(Eval("atan(q1)", 0.7, 0), std::atan(0.7));
  EXPECT_EQ(Eval("sign(q1)", -0.7, 0), -1.0);
  EXPECT_EQ(Eval("sign(q1)", 0.0, 0), 0.0);
  EXPECT_EQ(Eval("sign(q1)", 2.0, 0), 1.0);
  EXPECT_EQ(Eval("if(u1 < 0, 1, 2)", 0, 0, -0.1), 1.0);
  EXPECT_EQ(Eval("if(u1 < 0, 1, 2)", 0, 0, 0.0), 2.0);
  EXPECT_EQ(Eval("if(u1 <= 0, 1, 2)", 0, 0, 0.0), 1.0);
  EXPECT_EQ(Eval("if(q1 > q2, q1, q2)", 0.2, 0.5), 0.5);
  EXPECT_EQ(Eval("if(q1 >= 0.2, q1, q2)", 0.2, 0.5), 0.2);
  // Folding: a constant condition selects its branch at parse time.
  EXPECT_TRUE(Expression::Parse("if(m > 2, 1, q1)", Symbols()).is_constant());
  EXPECT_DOUBLE_EQ(Eval("30 deg", 0, 0), std::numbers::pi / 6);
  EXPECT_DOUBLE_EQ(Eval("600 mm + 1 km", 0, 0), 1000.6);
  EXPECT_DOUBLE_EQ(Eval("2kN * q1", 0.5, 0), 1000.0);
  EXPECT_DOUBLE_EQ(Eval("36 km/h", 0, 0), 10.0);       // a compound unit, no spaces
  EXPECT_DOUBLE_EQ(Eval("2 kN·mm/deg", 0, 0), 2.0 * 180.0 / std::numbers::pi);
  EXPECT_DOUBLE_EQ(Eval("3 mm*q1", 0.5, 0), 0.0015);   // mm*q1 is no unit: 3 mm times q1
  EXPECT_DOUBLE_EQ(Eval("30°", 0, 0), std::numbers::pi / 6);
}

TEST(FunctionsTest, ErrorsNameTheFix) {
  EXPECT_NE(ErrorOf("if(q1, 1, 2)").find("compares two expressions"), std::string::npos);
  EXPECT_NE(ErrorOf("if(q1 == 0, 1, 2)").find("equality"), std::string::npos);
  EXPECT_NE(ErrorOf("if(q1 < 0, 1)").find("three arguments"), std::string::npos);
  EXPECT_NE(ErrorOf("atan2(q1)").find("two arguments"), std::string::npos);
  EXPECT_NE(ErrorOf("sinh(q1)").find("atan2"), std::string::npos);  // the list is complete
  EXPECT_NE(ErrorOf("2 m").find("ambiguous"), std::string::npos);   // m is a parameter here
  EXPECT_NE(ErrorOf("2 t").find("ambiguous"), std::string::npos);   // t is time
  EXPECT_NE(ErrorOf("2 kg/m").find("ambiguous"), std::string::npos);  // m inside a compound
}

TEST(FunctionsTest, DepthLimitRefusesInsteadOfCrashing) {
  const std::string parens = std::string(30000, '(') + "q1" + std::string(30000, ')');
  EXPECT_NE(ErrorOf(parens).find("nests deeper than"), std::string::npos);
  std::string chain = "q1";
  for (int i = 0; i < 30000; ++i) chain += " + q1";
  EXPECT_NE(ErrorOf(chain).find("nests deeper than"), std::string::npos);
  std::string minus(30000, '-');
  EXPECT_NE(ErrorOf(minus + "q1").find("nests deeper than"), std::string::npos);
  std::string calls;
  for (int i = 0; i < 30000; ++i) calls += "sin(";
  EXPECT_NE(ErrorOf(calls + "q1" + std::string(30000, ')')).find("nests deeper than"),
            std::string::npos);
  std::string powers = "q1";
  for (int i = 0; i < 30000; ++i) powers += "^q1";
  EXPECT_NE(ErrorOf(powers).find("nests deeper than"), std::string::npos);
  // Just inside the limit parses.
  const int ok = kMaxExpressionDepth - 1;
  EXPECT_EQ(ErrorOf(std::string(ok, '(') + "q1" + std::string(ok, ')')), "no error");
}

// f(q1, q2) on Jet<double> and Jet<AutoDiff>: d1, d2 along q(s) = q + s q̇ + s²/2 q̈ and ∂/∂q
// against central differences; the AutoDiff and Jet<AutoDiff> partials agree.
void CheckDerivatives(const std::string& text, double q1, double q2) {
  SCOPED_TRACE(text);
  const Expression e = Expression::Parse(text, Symbols());
  const double q[2] = {q1, q2}, qd[2] = {0.9, -1.3}, qdd[2] = {0.4, 0.7};
  auto value = [&](double s, double dq1 = 0.0, double dq2 = 0.0) {
    const double qs[2] = {q[0] + s * qd[0] + 0.5 * s * s * qdd[0] + dq1,
                          q[1] + s * qd[1] + 0.5 * s * s * qdd[1] + dq2};
    return Evaluate(e, Variables<double>{0.1, qs, {}, {}, {}});
  };
  Jet<double> jq[2];
  Jet<AutoDiff> aq[2];
  for (int k = 0; k < 2; ++k) {
    jq[k].v = q[k];
    jq[k].d1 = qd[k];
    jq[k].d2 = qdd[k];
    jq[k].n = 2;
    jq[k].dq[k] = 1.0;
    aq[k].v = AutoDiff(q[k], Derivatives::Unit(2, k));
    aq[k].d1 = AutoDiff(qd[k], Derivatives::Zero(2));
    aq[k].d2 = AutoDiff(qdd[k], Derivatives::Zero(2));
    aq[k].n = 2;
    aq[k].dq[k] = AutoDiff(1.0, Derivatives::Zero(2));
  }
  const Jet<double> j = Evaluate(e, Variables<Jet<double>>{Jet<double>(0.1), jq, {}, {}, {}});
  const double h = 1e-4;
  // Central differences are good to ~h² times the third derivative: relative tolerances.
  auto near = [](double exact, double fd, double tol) {
    EXPECT_NEAR(exact, fd, tol * (1.0 + std::abs(exact)));
  };
  EXPECT_NEAR(j.v, value(0.0), 1e-15);
  near(j.d1, (value(h) - value(-h)) / (2 * h), 1e-7);
  near(j.d2, (value(h) - 2 * value(0.0) + value(-h)) / (h * h), 2e-5);
  near(j.dq[0], (value(0, h) - value(0, -h)) / (2 * h), 1e-7);
  near(j.dq[1], (value(0, 0, h) - value(0, 0, -h)) / (2 * h), 1e-7);
  const Jet<AutoDiff> ja = Evaluate(
      e, Variables<Jet<AutoDiff>>{Jet<AutoDiff>(0.1), aq, {}, {}, {}});
  EXPECT_NEAR(ja.v.value(), j.v, 1e-15);
  EXPECT_NEAR(ja.d1.value(), j.d1, 1e-13);
  EXPECT_NEAR(ja.d2.value(), j.d2, 1e-12);
  // ∂(dφ/dt)/∂q_k by AutoDiff against the difference of the jet's d1.
  auto d1_at = [&](double dq1, double dq2) {
    Jet<double> jj[2] = {jq[0], jq[1]};
    jj[0].v += dq1;
    jj[1].v += dq2;
    return Evaluate(e, Variables<Jet<double>>{Jet<double>(0.1), jj, {}, {}, {}}).d1;
  };
  ASSERT_EQ(ja.d1.derivatives().size(), 2);
  near(ja.d1.derivatives()(0), (d1_at(h, 0) - d1_at(-h, 0)) / (2 * h), 1e-6);
  near(ja.d1.derivatives()(1), (d1_at(0, h) - d1_at(0, -h)) / (2 * h), 1e-6);
  const AutoDiff ad[2] = {AutoDiff(q[0], Derivatives::Unit(2, 0)), AutoDiff(q[1], Derivatives::Unit(2, 1))};
  const AutoDiff a = Evaluate(e, Variables<AutoDiff>{AutoDiff(0.1, Derivatives::Zero(2)), ad, {}, {}, {}});
  EXPECT_NEAR(a.value(), j.v, 1e-15);
  EXPECT_NEAR(a.derivatives()(0), j.dq[0], 1e-14);
  EXPECT_NEAR(a.derivatives()(1), j.dq[1], 1e-14);
}

TEST(FunctionsTest, DerivativesAreExactOnAutoDiffAndJets) {
  for (const auto& [q1, q2] : {std::pair{0.3, 0.8}, {0.3, -0.8}, {-0.9, 0.2}, {-0.2, -0.25}}) {
    CheckDerivatives("atan2(q1, q2)", q1, q2);
    CheckDerivatives("atan2(m * q1 + q2, q1 - 2 * q2)", q1, q2);
  }
  CheckDerivatives("tanh(2 * q1 - q2)", 0.3, 0.1);
  CheckDerivatives("asin(q1 * q2)", 0.6, 0.9);
  CheckDerivatives("acos(q1 - q2 / 2)", 0.3, 0.5);
  CheckDerivatives("atan(q1 ^ 2 + q2)", 0.7, -1.2);
  CheckDerivatives("sign(q1) * q2 ^ 2", -0.7, 1.2);
  CheckDerivatives("if(q1 < q2, sin(q1) * q2, q1 ^ 3)", 0.2, 0.5);
  CheckDerivatives("if(q1 < q2, sin(q1) * q2, q1 ^ 3)", 0.7, 0.5);
}

SymbolTable WithTable() {
  SymbolTable s = Symbols();
  s.AddTable("Cp", Table{"Cp", {0.0, 1.0, 3.0}, {0.0, 2.0, 1.0}, {}});
  return s;
}

TEST(TableTest, InterpolatesLinearlyAndIsConstantBeyondTheEnds) {
  const SymbolTable s = WithTable();
  auto at = [&](double q1) {
    const Expression e = Expression::Parse("Cp(q1)", s);
    const double q[2] = {q1, 0.0};
    return Evaluate(e, Variables<double>{0.0, q, {}, {}, {}});
  };
  EXPECT_DOUBLE_EQ(at(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(at(0.0), 0.0);
  EXPECT_DOUBLE_EQ(at(0.25), 0.5);
  EXPECT_DOUBLE_EQ(at(1.0), 2.0);
  EXPECT_DOUBLE_EQ(at(2.0), 1.5);
  EXPECT_DOUBLE_EQ(at(3.0), 1.0);
  EXPECT_DOUBLE_EQ(at(7.0), 1.0);
  // A table at a constant folds; derivatives are the segment's slope (0 beyond the ends).
  EXPECT_TRUE(Expression::Parse("Cp(0.5) * 2", s).is_constant());
  const Expression e = Expression::Parse("Cp(2 * q1)", s);
  for (const auto& [q1, slope] : {std::pair{0.25, 4.0}, {1.0, -1.0}, {-0.1, 0.0}, {2.0, 0.0}}) {  // d/dq1 = 2 · slope
    const AutoDiff aq[2] = {AutoDiff(q1, Derivatives::Unit(2, 0)), AutoDiff(0.0, Derivatives::Unit(2, 1))};
    const AutoDiff a = Evaluate(e, Variables<AutoDiff>{AutoDiff(0.0), aq, {}, {}, {}});
    EXPECT_DOUBLE_EQ(a.derivatives().size() ? a.derivatives()(0) : 0.0, slope) << q1;
    Jet<double> jq[2];
    jq[0].v = q1;
    jq[0].d1 = 0.7;
    jq[0].d2 = 0.3;
    jq[0].n = 2;
    jq[0].dq[0] = 1.0;
    const Jet<double> j = Evaluate(e, Variables<Jet<double>>{Jet<double>(0.0), jq, {}, {}, {}});
    EXPECT_DOUBLE_EQ(j.dq[0], slope) << q1;
    EXPECT_DOUBLE_EQ(j.d1, slope * 0.7) << q1;
    EXPECT_DOUBLE_EQ(j.d2, slope * 0.3) << q1;
  }
  std::string why;
  try {
    Expression::Parse("Cp * 2", s);
  } catch (const ExpressionError& err) {
    why = err.message;
  }
  EXPECT_NE(why.find("Cp(x)"), std::string::npos) << why;
}

TEST(TableTest, TwoDimensionalTablesAreBilinearAndClamped) {
  SymbolTable s = Symbols();
  // z = x + 10 y + x y on the grid: bilinear reproduces it exactly inside.
  Table t{"t", {0.0, 1.0, 3.0}, {0.0, 2.0}, {}};
  for (double x : t.x)
    for (double y : t.y) t.z.push_back(x + 10 * y + x * y);
  s.AddTable("Ct", t);
  const Expression e = Expression::Parse("Ct(q1, q2)", s);
  auto at = [&](double q1, double q2) {
    const double q[2] = {q1, q2};
    return Evaluate(e, Variables<double>{0.0, q, {}, {}, {}});
  };
  EXPECT_DOUBLE_EQ(at(0.5, 1.0), 0.5 + 10 + 0.5);
  EXPECT_DOUBLE_EQ(at(2.0, 0.5), 2.0 + 5 + 1.0);
  EXPECT_DOUBLE_EQ(at(-1.0, 1.0), at(0.0, 1.0));  // clamped in x
  EXPECT_DOUBLE_EQ(at(2.0, 5.0), at(2.0, 2.0));   // clamped in y
  // Partials: 1 + y and 10 + x inside; 0 along a clamped axis.
  for (const auto& [q1, q2, d1, d2] : {std::tuple{0.5, 1.0, 2.0, 10.5}, {2.0, 0.5, 1.5, 12.0},
                                       {-1.0, 1.0, 0.0, 10.0}, {2.0, 5.0, 3.0, 0.0}}) {
    const AutoDiff aq[2] = {AutoDiff(q1, Derivatives::Unit(2, 0)), AutoDiff(q2, Derivatives::Unit(2, 1))};
    const AutoDiff a = Evaluate(e, Variables<AutoDiff>{AutoDiff(0.0), aq, {}, {}, {}});
    EXPECT_NEAR(a.derivatives()(0), d1, 1e-14) << q1 << ", " << q2;
    EXPECT_NEAR(a.derivatives()(1), d2, 1e-14) << q1 << ", " << q2;
  }
  std::string why;
  try {
    Expression::Parse("Ct(q1)", s);
  } catch (const ExpressionError& err) {
    why = err.message;
  }
  EXPECT_NE(why.find("two arguments"), std::string::npos) << why;
}

TEST(UnitsTest, ParsedAndConvertedOrRefused) {
  std::string why;
  const auto check = [&](const char* text, double to_si, const char* si) {
    const std::optional<Unit> u = ParseUnit(text, &why);
    ASSERT_TRUE(u.has_value()) << text << ": " << why;
    EXPECT_NEAR(u->to_si, to_si, 1e-12 * to_si) << text;
    EXPECT_EQ(u->si, si) << text;
  };
  check("mm", 1e-3, "m");
  check("kN/mm", 1e6, "N/m");
  check("N·m/rad", 1.0, "N·m/rad");
  check("N*m*s/rad", 1.0, "N·m·s/rad");
  check("kg·m²", 1.0, "kg·m²");
  check("m/s^2", 1.0, "m/s²");
  check("g·cm²", 1e-7, "kg·m²");
  check("deg", std::numbers::pi / 180, "rad");
  check("rpm", 2 * std::numbers::pi / 60, "rad/s");
  check("1/s", 1.0, "1/s");
  check("kN·m/deg", 180e3 / std::numbers::pi, "N·m/rad");
  EXPECT_FALSE(ParseUnit("furlong", &why).has_value());
  EXPECT_NE(why.find("'furlong'"), std::string::npos);
  EXPECT_FALSE(ParseUnit("m/s/s", &why).has_value());
  const std::optional<Unit> torque = ParseUnit("N·m", &why);
  const std::optional<Unit> energy = ParseUnit("J", &why);
  ASSERT_TRUE(torque && energy);
  EXPECT_EQ(torque->dim, energy->dim);
}

}  // namespace
}  // namespace hybridtest::modelfile
