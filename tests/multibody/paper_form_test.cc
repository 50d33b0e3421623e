// PaperFormFromKane: the paper's M ẋ + g = 0 (Eq. 18) from the engine's Kane form, checked
// against Eq. (21) for every built-in model, against the printed Eq. (19) for the rotor, and
// the printed Eq. (20) shown to be wrong where PAPER-NOTES says it is.
#include "hybridtest/multibody/paper_form.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::CoordinateScales;
using test_support::DefaultModel;
using test_support::RandomForces;
using test_support::RandomState;
using test_support::RelativeError;

// Eq. (21): ẋ = −M_paper⁻¹ g_paper equals CalcStateDerivative for each built-in model.
TEST(PaperFormTest, SolvingThePaperFormGivesTheStateDerivative) {
  std::mt19937 rng(11);
  for (const std::string& name : models::ModelNames()) {
    const models::BuiltModel built = DefaultModel(name);
    const Model& model = built.model;
    Data<double> data(model);
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
      const Eigen::VectorXd r = RandomForces(rng, model.num_slots(), 500.0);
      const double t = 0.25 * trial;
      Eigen::VectorXd xdot(model.num_states());
      CalcStateDerivative<double>(model, data, t, x, r, xdot);
      const PaperForm form = PaperFormFromKane(data);
      ASSERT_EQ(form.M.rows(), 2 * model.num_coordinates());
      ASSERT_EQ(form.g.size(), 2 * model.num_coordinates());
      const Eigen::VectorXd from_paper = -form.M.partialPivLu().solve(form.g);
      EXPECT_LT(RelativeError(from_paper, xdot), 1e-12) << name << " trial " << trial;
      // And the residual of Eq. (18) itself vanishes.
      EXPECT_LT(RelativeError(form.M * xdot + form.g, Eigen::VectorXd::Zero(xdot.size())),
                1e-10)
          << name;
    }
  }
}

// The same after the three separate calls instead of CalcStateDerivative.
TEST(PaperFormTest, WorksAfterSeparateKinematicsMassMatrixAndForcing) {
  const models::BuiltModel built = DefaultModel("spinning_top");
  const Model& model = built.model;
  std::mt19937 rng(12);
  const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 3.0);
  const Eigen::VectorXd r(0);
  Data<double> data(model);
  CalcKinematics<double>(model, data, 0.3, x);
  CalcMassMatrix<double>(model, data);
  CalcForcing<double>(model, data, r);
  const PaperForm form = PaperFormFromKane(data);
  const Eigen::VectorXd xdot = test_support::StateDerivative(model, 0.3, x, r);
  EXPECT_LT(RelativeError(-form.M.partialPivLu().solve(form.g), xdot), 1e-12);
  // The top has non-identity kinematics: the upper block of g is −W u, not −u.
  EXPECT_GT((form.g.head(3) + x.tail(3)).norm(), 1e-3);
}

// Table 1 values used by the rotor defaults.
constexpr double kLb = 0.5, kMb = 1.96, kIg = 0.1, kZeta = 1.0, kFw = 100.0, kDg = 100.0,
                 kG = 9.82, kT0 = 0.5;

// Eq. (19): the lower block of M_paper is the negative arrow matrix.
TEST(PaperFormTest, RotorMassMatrixIsPrintedEquation19) {
  const models::BuiltModel built = DefaultModel("rotor");
  std::mt19937 rng(19);
  Data<double> data(built.model);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
    Eigen::VectorXd xdot(8);
    CalcStateDerivative<double>(built.model, data, 1.0, x, Eigen::VectorXd::Zero(3), xdot);
    const PaperForm form = PaperFormFromKane(data);
    Eigen::MatrixXd eq19 = Eigen::MatrixXd::Zero(8, 8);
    eq19.topLeftCorner(4, 4).setIdentity();
    double hub = -kIg;
    for (int i = 0; i < 3; ++i) {
      eq19(4 + i, 4 + i) = -kMb;
      eq19(4 + i, 7) = eq19(7, 4 + i) = -kLb * kMb;
      hub -= kMb * (kLb * kLb + x(i) * x(i));
    }
    eq19(7, 7) = hub;
    EXPECT_LT((form.M - eq19).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
  }
}

// The printed Eq. (20), transcribed literally: g_paper (8) at (t, x, r).
Eigen::VectorXd PrintedEquation20(double t, const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
  const double ramp = 1.0 - std::exp(-t / kT0);
  Eigen::VectorXd g(8);
  g.head(4) = -x.tail(4);
  const double u4 = x(7), q4 = x(3);
  double hub = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double psi = 2.0 * std::numbers::pi * i / 3.0;
    const double qi = x(i), ui = x(4 + i);
    g(4 + i) = ramp * (kFw - kG * kMb * std::sin(q4 + psi)) - r(i) - kMb * kZeta * ui +
               kMb * qi * u4 * u4;
    hub += ramp * (kFw * kLb - kG * kMb * qi * std::cos(q4 + psi)) + 2.0 * kMb * qi * ui * u4;
  }
  g(7) = hub - kDg * u4;
  return g;
}

// The hub row as derived independently (by hand and by SymPy's KanesMethod in the oracle's
// self-test): with v_i = −q_i u4 b̂_x + (u_i + l_b u4) b̂_y and a_rem,i = −(2 u_i u4 + l_b u4²) b̂_x
// − q_i u4² b̂_y, the hub's generalized inertia force is Σ_i −2 m_b q_i u_i u4 (a Coriolis term:
// MINUS, where Eq. 20 prints PLUS), gravity contributes −m_b G ρ (q_i cos θ_i + l_b sin θ_i)
// (the l_b sin θ_i terms cancel for equal blades at 120°) and the r_i terms cancel against the
// root reactions on the hub.
double DerivedHubRow(double t, const Eigen::VectorXd& x) {
  const double ramp = 1.0 - std::exp(-t / kT0);
  const double u4 = x(7), q4 = x(3);
  double hub = -kDg * u4;
  for (int i = 0; i < 3; ++i) {
    const double theta = q4 + 2.0 * std::numbers::pi * i / 3.0;
    const double qi = x(i), ui = x(4 + i);
    hub += ramp * (kFw * kLb - kG * kMb * (qi * std::cos(theta) + kLb * std::sin(theta))) -
           2.0 * kMb * qi * ui * u4;
  }
  return hub;
}

// Finding: the printed Eq. (20) disagrees with the engine in exactly one entry, the hub row
// (row 8 of g_paper), by the sign of the Coriolis term 2 m_b q_i u_i u4: the printed row
// minus the engine's is 4 m_b Σ_i q_i u_i u4. Rows 1–7 (−u and the three blade rows,
// including the centrifugal term +m_b q_i u4²) agree. At states with q_i u_i u4 = 0 (e.g. the
// paper's zero initial state) the error is invisible, which is how it can survive a run.
TEST(PaperFormTest, PrintedEquation20HasTheWrongCoriolisSignInTheHubRow) {
  const models::BuiltModel built = DefaultModel("rotor");
  std::mt19937 rng(20);
  Data<double> data(built.model);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
    for (int i = 0; i < 3; ++i) x(i) = (i % 2 == 0 ? 1.0 : -1.0) * (0.02 + std::abs(x(i)));
    x(7) = 1.0 + std::abs(x(7));  // non-zero hub speed
    for (int i = 0; i < 3; ++i) x(4 + i) = (i % 2 == 0 ? 1.0 : -1.0) * (0.5 + std::abs(x(4 + i)));
    const Eigen::VectorXd r = RandomForces(rng, 3, 500.0);
    const double t = 0.1 + 0.2 * trial;
    Eigen::VectorXd xdot(8);
    CalcStateDerivative<double>(built.model, data, t, x, r, xdot);
    const PaperForm form = PaperFormFromKane(data);
    const Eigen::VectorXd printed = PrintedEquation20(t, x, r);
    const double tol = 1e-10 * std::max(1.0, printed.cwiseAbs().maxCoeff());
    // Rows 1–7 agree.
    for (int row = 0; row < 7; ++row) {
      EXPECT_NEAR(form.g(row), printed(row), tol) << "row " << row + 1 << " trial " << trial;
    }
    // Row 8 disagrees, by exactly 4 m_b Σ q_i u_i u4 (non-zero by construction: q_i u_i > 0).
    double coriolis = 0.0;
    for (int i = 0; i < 3; ++i) coriolis += kMb * x(i) * x(4 + i) * x(7);
    ASSERT_GT(std::abs(4.0 * coriolis), 1e-2);
    EXPECT_GT(std::abs(printed(7) - form.g(7)), 1e-2) << "trial " << trial;
    EXPECT_NEAR(printed(7) - form.g(7), 4.0 * coriolis, tol) << "trial " << trial;
    // The engine agrees with the independently derived hub row.
    EXPECT_NEAR(form.g(7), DerivedHubRow(t, x), tol) << "trial " << trial;
  }
}

}  // namespace
}  // namespace hybridtest::multibody
