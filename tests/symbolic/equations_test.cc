// The engine on the Symbolic scalar (decision 0019): its M and f, evaluated at random states,
// equal the double engine's; the rotor's M has the paper's Eq. (19) structure; the printers'
// dialects and names.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/models/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/multibody/symbolic.h"
#include "hybridtest/symbolic/equations.h"
#include "hybridtest/symbolic/print_expression.h"
#include "hybridtest/symbolic/simplify.h"
#include "support/chain_model_file.h"

namespace hybridtest::symbolic {
namespace {

double Evaluate(const GiNaC::ex& e, const GiNaC::exmap& at) {
  const GiNaC::ex v = GiNaC::evalf(e.subs(at));
  EXPECT_TRUE(GiNaC::is_a<GiNaC::numeric>(v)) << "not a number after substitution: " << v;
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

// M and f from DeriveEquations at `trials` random states against CalcMassMatrix/CalcForcing.
void ExpectSymbolicEqualsNumeric(const multibody::Model& model, int trials) {
  const Equations eq = DeriveEquations(model);
  const int n = model.num_coordinates();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.1, 1.1), speed(-5.0, 5.0),
      force(-2000.0, 2000.0), time(0.0, 5.0);
  multibody::Data<double> data(model);
  for (int trial = 0; trial < trials; ++trial) {
    GiNaC::exmap at;
    Eigen::VectorXd x(model.num_states());
    Eigen::VectorXd r(model.num_slots());
    for (int k = 0; k < n; ++k) {
      x(k) = coordinate(rng);
      x(n + k) = speed(rng);
      at[eq.q[k]] = x(k);
      at[eq.u[k]] = x(n + k);
    }
    for (int k = 0; k < model.num_extra_states(); ++k) {
      x(2 * n + k) = coordinate(rng);
      at[eq.z[k]] = x(2 * n + k);
    }
    for (int s = 0; s < model.num_slots(); ++s) {
      r(s) = force(rng);
      at[eq.r[s]] = r(s);
    }
    const double t = time(rng);
    at[eq.t] = t;
    // Large equations: their common subexpressions, in order (shared.h).
    for (const auto& [symbol, value] : eq.shared.definitions) at[symbol] = GiNaC::evalf(value.subs(at));
    multibody::CalcKinematics<double>(model, data, t, x);
    multibody::CalcMassMatrix<double>(model, data);
    multibody::CalcForcing<double>(model, data, r);
    const double scale_M = std::max(1.0, data.M.cwiseAbs().maxCoeff());
    const double scale_g = std::max(1.0, data.g.cwiseAbs().maxCoeff());
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        EXPECT_NEAR(Evaluate(eq.M[j][k], at), data.M(j, k), 1e-12 * scale_M) << j << "," << k;
      }
      EXPECT_NEAR(Evaluate(eq.f[j], at), data.g(j), 1e-12 * scale_g) << j;
      // Fr + Fr* = 0 at u̇ = M⁻¹ f (Kane's equations).
    }
    const Eigen::VectorXd udot = data.M.ldlt().solve(data.g);
    for (int k = 0; k < n; ++k) at[eq.udot[k]] = udot(k);
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(Evaluate(eq.Fr[j] + eq.Fr_star[j], at), 0.0, 1e-9 * scale_g) << j;
    }
  }
}

TEST(SymbolicEngine, BuiltInModelsEqualTheDoubleEngine) {
  for (const std::string& name : models::ModelNames()) {
    SCOPED_TRACE(name);
    const auto built = models::BuildModel(name, 3, models::DefaultParameters(name, 3));
    ExpectSymbolicEqualsNumeric(built.model, 10);
  }
}

TEST(SymbolicEngine, ExampleModelFilesEqualTheDoubleEngine) {
  for (const char* stem : {"cart_pendulum", "double_pendulum", "rotor", "spinning_top",
                           "wind_turbine"}) {
    SCOPED_TRACE(stem);
    const auto file = modelfile::LoadModelFile(std::string(HYBRIDTEST_SOURCE_DIR) +
                                               "/examples/models/" + stem + ".yaml");
    ExpectSymbolicEqualsNumeric(modelfile::BuildModelFile(file, file.parameters).model, 5);
  }
}

// Issue 47: a chain too large to expand keeps the engine's expressions with named common
// subexpressions (before, the expansion did not finish in minutes for six links), and they
// equal the double engine.
TEST(SymbolicEngine, LargeChainIsSharedAndEqualsTheDoubleEngine) {
  const std::string path = ::testing::TempDir() + "/symbolic_chain6.yaml";
  std::ofstream(path) << test_support::ChainModelFile(6, 1);
  const auto file = modelfile::LoadModelFile(path);
  const auto built = modelfile::BuildModelFile(file, file.parameters);
  EXPECT_FALSE(DeriveEquations(built.model).shared.definitions.empty());
  ExpectSymbolicEqualsNumeric(built.model, 3);
}

// Issue 47: numbers print as the model wrote them (exact decimal arithmetic, not the last bits
// of a float sum), and terms in an order of their own, not GiNaC's address-dependent one.
TEST(PrintExpression, NumbersAsWrittenAndTermsInAFixedOrder) {
  using multibody::Symbolic;
  const NameMap none;
  EXPECT_EQ(PrintExpression((Symbolic(0.1) + Symbolic(0.2)).ex(), Dialect::kPlain, none), "0.3");
  EXPECT_EQ(PrintExpression((Symbolic(1.1) * Symbolic(9.81)).ex(), Dialect::kSympy, none), "10.791");
  EXPECT_EQ(PrintExpression((Symbolic(0.1) + 3.0 * Symbolic(1.96) * 0.5 * 0.5).ex(),
                            Dialect::kPlain, none), "1.57");  // I_g + 3 m_b l_b²
  EXPECT_EQ(PrintExpression(Symbolic(0.5).ex(), Dialect::kPlain, none), "1/2");
  // g m_b cos(2π/3) as the rotor's builder computes it in doubles: 9.623599999999996.
  EXPECT_EQ(PrintExpression(Symbolic(-9.82 * 1.96 * std::cos(2.0 * M_PI / 3.0)).ex(),
                            Dialect::kPlain, none), "9.6236");
  EXPECT_EQ(PrintExpression(GiNaC::numeric(1.0 / 3.0), Dialect::kPlain, none), "0.333333333333333");
  const GiNaC::realsymbol b("b"), a("a"), c("c");
  EXPECT_EQ(PrintExpression(c - b + a, Dialect::kPlain, none), "a - b + c");
  EXPECT_EQ(PrintExpression(-2 * c * a * b, Dialect::kPlain, none), "-2*a*b*c");
  // A lone inverse (a common subexpression of the spinning top): printed -a before.
  EXPECT_EQ(PrintExpression(GiNaC::pow(a, -1), Dialect::kSympy, none), "1/a");
  EXPECT_EQ(PrintExpression(GiNaC::pow(a + b, -2), Dialect::kPlain, none), "1/(a + b)^2");
}

// Issue 47: a number the model computed in doubles (a blade at 2π/3: sin and cos of a float
// angle) prints in its short exact form, not as 15 digits that differ in the last one between
// blades (0.866025403784439 and 0.866025403784438), nor as a coefficient "1" (-1*r2).
TEST(PrintExpression, FloatNumbersInTheirShortExactForm) {
  using multibody::Symbolic;
  const NameMap none;
  const GiNaC::realsymbol x("x");
  const double s2 = std::sin(2.0 * M_PI / 3.0), s4 = std::sin(4.0 * M_PI / 3.0);
  EXPECT_EQ(PrintExpression((Symbolic(s2) * Symbolic(x)).ex(), Dialect::kPlain, none),
            "sqrt(3)*x/2");
  EXPECT_EQ(PrintExpression((Symbolic(s4) * Symbolic(x)).ex(), Dialect::kSympy, none),
            "-sp.sqrt(3)*x/2");
  EXPECT_EQ(PrintExpression(Symbolic(s2).ex(), Dialect::kLatex, none), "\\frac{\\sqrt{3}}{2}");
  // g m_b sin(2π/3), as the rotor's builder computes it: 9.6236·√3.
  EXPECT_EQ(PrintExpression((Symbolic(9.82 * 1.96 * s2) * Symbolic(x)).ex(), Dialect::kPlain,
                            none), "9.6236*sqrt(3)*x");
  EXPECT_EQ(PrintExpression((Symbolic(std::sin(M_PI / 4.0)) * Symbolic(x)).ex(), Dialect::kPlain,
                            none), "sqrt(2)*x/2");
  // −cos(π)·(1 + 2⁻⁵²): a whole number in floating point.
  EXPECT_EQ(PrintExpression((Symbolic(-1.0000000000000002) * Symbolic(x)).ex(), Dialect::kPlain,
                            none), "-x");
  // The model's own numbers and other floats print as before.
  EXPECT_EQ(PrintExpression((Symbolic(0.866) * Symbolic(x)).ex(), Dialect::kPlain, none),
            "0.866*x");
  EXPECT_EQ(PrintExpression(GiNaC::numeric(1.0 / 3.0), Dialect::kPlain, none), "0.333333333333333");
  // C keeps the double itself (a literal that reads back exactly).
  EXPECT_EQ(PrintExpression(Symbolic(s2).ex(), Dialect::kC, none), "0.86602540378443871");
}

TEST(SymbolicEngine, RotorMassMatrixHasThePapersArrowStructure) {
  const auto built = models::BuildModel("rotor", 3, models::DefaultParameters("rotor", 3));
  const Equations eq = DeriveEquations(built.model);
  const double m_b = 1.96, l_b = 0.5, I_g = 0.1;
  // Eq. (19), lower block negated: diag m_b, arrow m_b l_b, hub I_g + Σ m_b (l_b² + q_i²).
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      // Exactly m_b as the model gives it (the rational 49/25 of 1.96; issue 47).
      EXPECT_TRUE((eq.M[i][k] - (i == k ? GiNaC::ex(GiNaC::numeric(49, 25)) : 0)).is_zero())
          << eq.M[i][k];
    }
    EXPECT_NEAR(GiNaC::ex_to<GiNaC::numeric>(eq.M[i][3]).to_double(), m_b * l_b, 1e-15);
  }
  GiNaC::ex hub = I_g;
  for (int i = 0; i < 3; ++i) hub += m_b * (l_b * l_b + GiNaC::pow(eq.q[i], 2));
  // Equal up to the rounding of the float coefficients (1e-16 relative).
  const GiNaC::ex difference = eq.M[3][3] - hub;
  for (const double q : {-1.0, 0.3, 2.0}) {
    const GiNaC::exmap at = {{eq.q[0], q}, {eq.q[1], 0.5 * q}, {eq.q[2], -q}};
    EXPECT_NEAR(Evaluate(difference, at), 0.0, 1e-12) << eq.M[3][3];
  }
  // The hub row of f: no restoring force (the tip's and the root's cancel, Eq. 10).
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(eq.f[3].has(eq.r[i])) << eq.f[3];
  // The blade rows: −r_i, −ζ_b m_b u_i and the centrifugal m_b q_i u_4².
  EXPECT_TRUE(eq.f[0].has(eq.r[0]));
  const GiNaC::ex centrifugal = eq.f[0].expand().coeff(eq.u[3], 2);  // m_b q_1
  EXPECT_NEAR(Evaluate(centrifugal, {{eq.q[0], 1.0}}), m_b, 1e-12) << eq.f[0];
  EXPECT_NEAR(Evaluate(centrifugal, {{eq.q[0], 0.0}}), 0.0, 1e-12) << eq.f[0];
}

TEST(SymbolicEngine, ModelFileWithABranchThrowsANamedError) {
  const std::string path = testing::TempDir() + "/branch.yaml";
  std::ofstream(path) << "name: branch\nparameters:\n  k: {value: 1.0, unit: N/m}\ncoordinates:\n  - {name: x, unit: m}\n"
                         "points:\n  - {name: P, from: O, frame: N, position: [x, 0, 0]}\n"
                         "particles:\n  - {name: p, point: P, mass: 1}\n"
                         "forces:\n  - {name: f, point: P, expressed_in: N, value: "
                         "[\"if(x > 0, -k * x, 0)\", 0, 0]}\n";
  const auto file = modelfile::LoadModelFile(path);
  const auto built = modelfile::BuildModelFile(file, file.parameters);
  try {
    DeriveEquations(built.model);
    FAIL() << "expected a ModelError";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("branches on a value"), std::string::npos) << e.what();
  }
}

TEST(PrintExpression, DialectsAndNames) {
  const GiNaC::realsymbol x("x"), theta("theta2");
  const GiNaC::ex e = GiNaC::pow(x, 2) / 2 - 1.5 * GiNaC::sin(theta);
  const NameMap plain;
  EXPECT_EQ(PrintExpression(GiNaC::pow(x, 2), Dialect::kSympy, plain), "x**2");
  EXPECT_EQ(PrintExpression(GiNaC::numeric(1, 2) * x, Dialect::kSympy, plain), "x/2");
  EXPECT_EQ(PrintExpression(GiNaC::numeric(1, 2), Dialect::kSympy, plain), "sp.Rational(1, 2)");
  EXPECT_EQ(PrintExpression(GiNaC::sin(x), Dialect::kSympy, plain), "sp.sin(x)");
  EXPECT_EQ(PrintExpression(GiNaC::numeric(1, 2) * x, Dialect::kLatex, plain), "\\frac{x}{2}");
  EXPECT_EQ(PrintExpression(-x, Dialect::kPlain, plain), "-x");
  const NameMap latex = {{"theta2", LatexName("theta2")}};
  EXPECT_NE(PrintExpression(e, Dialect::kLatex, latex).find("\\sin{\\left(\\theta_{2}\\right)}"),
            std::string::npos);
  EXPECT_EQ(LatexName("u1_dot"), "\\dot{u}_{1}");
  EXPECT_EQ(LatexName("m_b"), "m_{b}");
  EXPECT_EQ(PythonName("lambda"), "lambda_");
  EXPECT_EQ(PythonName("blade1.m_b"), "blade1_m_b");
  EXPECT_EQ(PythonName("M"), "M_");
}

TEST(Simplify, PythagorasAndRoundingCollapse) {
  const GiNaC::realsymbol q("q");
  const double c = std::cos(2.0943951023931953), s = std::sin(2.0943951023931953);
  // (c cos q − s sin q)² + (s cos q + c sin q)² = 1 up to the rounding of c² + s².
  const GiNaC::ex a = c * GiNaC::cos(q) - s * GiNaC::sin(q);
  const GiNaC::ex b = s * GiNaC::cos(q) + c * GiNaC::sin(q);
  EXPECT_TRUE((Simplify(a * a + b * b) - 1).is_zero()) << Simplify(a * a + b * b);
  EXPECT_TRUE((Simplify(GiNaC::ex(2.0) * q) - 2 * q).is_zero());
}

// sin(x)^n, n ≥ 2, in every power, product and function argument, and a subexpression shared
// between two expressions simplified by one Simplifier.
TEST(Simplify, HigherPowersNestedArgumentsAndSharedSubexpressions) {
  const GiNaC::realsymbol q("q"), p("p");
  const GiNaC::ex s = GiNaC::sin(q), c = GiNaC::cos(q);
  const GiNaC::ex square = GiNaC::pow(s, 2) + GiNaC::pow(c, 2);
  EXPECT_TRUE((Simplify(GiNaC::pow(square, 2)) - 1).is_zero()) << Simplify(GiNaC::pow(square, 2));
  EXPECT_TRUE((Simplify(GiNaC::pow(s, 3) + s * GiNaC::pow(c, 2)) - s).is_zero());
  EXPECT_TRUE((Simplify(GiNaC::cos(p + square)) - GiNaC::cos(p + 1)).is_zero())
      << Simplify(GiNaC::cos(p + square));
  EXPECT_TRUE((Simplify(GiNaC::pow(s, -2) * p) - GiNaC::pow(s, -2) * p).is_zero());  // left alone
  Simplifier simplify;
  const GiNaC::ex shared = (p + s) * (p - s);
  const GiNaC::ex first = simplify(shared * c);
  const GiNaC::ex second = simplify(shared + GiNaC::pow(c, 2));
  EXPECT_TRUE((first - (p * p * c - c + GiNaC::pow(c, 3))).is_zero()) << first;
  EXPECT_TRUE((second - (p * p - 1 + 2 * GiNaC::pow(c, 2))).is_zero()) << second;
}

}  // namespace
}  // namespace hybridtest::symbolic
