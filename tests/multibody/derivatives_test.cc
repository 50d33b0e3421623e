// The exact derivatives the engine gets from AutoDiff: the coupling matrix B = ∂g/∂r and the
// state Jacobian J = ∂ẋ/∂x, against differences of the double-precision engine; and the
// AutoDiff instantiation's values against the double one.
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::CoordinateScales;
using test_support::DefaultModel;
using test_support::RandomForces;
using test_support::RandomState;
using test_support::RelativeError;

// g at (t, x, r) from the double engine.
Eigen::VectorXd Forcing(const Model& model, double t, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& r) {
  Data<double> data(model);
  CalcKinematics<double>(model, data, t, x);
  CalcForcing<double>(model, data, r);
  return data.g;
}

models::BuiltModel UnequalTwoBladeRotor() {
  models::ParameterSet p = models::DefaultParameters("rotor", 2);
  p.Set("blade2.l_b", 0.7, "test");
  p.Set("blade1.m_b", 2.5, "test");
  return models::BuildModel("rotor", 2, p);
}

// Regression: CalcCouplingMatrix and CalcStateJacobian once lost derivatives on the rotor. The
// time t had an empty derivative vector, and Eigen's AutoDiffScalar cannot make derivative
// expressions of different sizes coherent, so `-(r + c u) + ramp(t) f_w` silently dropped the
// r- and u-derivatives (B = [0; 0.5 …] instead of [−I; 0]). The engine now seeds every input
// with a full-size derivative vector.
// g is affine in r, so B e_i = g(r = e_i) − g(r = 0) exactly (up to rounding).
TEST(DerivativesTest, CouplingMatrixIsTheForcingDifference) {
  std::mt19937 rng(31);
  for (const models::BuiltModel& built : {DefaultModel("rotor"), UnequalTwoBladeRotor()}) {
    const Model& model = built.model;
    const int m = model.num_slots();
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
      const double t = 0.3 * trial;
      const Eigen::MatrixXd B = CalcCouplingMatrix(model, t, x);
      ASSERT_EQ(B.rows(), model.num_coordinates());
      ASSERT_EQ(B.cols(), m);
      const Eigen::VectorXd g0 = Forcing(model, t, x, Eigen::VectorXd::Zero(m));
      for (int s = 0; s < m; ++s) {
        const Eigen::VectorXd gs = Forcing(model, t, x, Eigen::VectorXd::Unit(m, s));
        EXPECT_LT((B.col(s) - (gs - g0)).cwiseAbs().maxCoeff(), 1e-10) << "slot " << s;
      }
    }
  }
}

// For the rotor, column i of B is −e_i: the restoring force acts as −r_i b̂_iy on tip i (partial
// velocity b̂_iy for u_i) and as the root reaction +r_i l_b ẑ on the hub; for the hub speed the
// tip's partial velocity is −q_i b̂_ix + l_b b̂_iy, giving −r_i l_b, which cancels the root
// reaction exactly. An internal force pair does no work on the rigid hub rotation, so the hub
// row of B is 0, not +l_b (and Eq. 20's hub row indeed has no r terms). B does not depend on
// the state.
TEST(DerivativesTest, RotorCouplingMatrixIsMinusIdentityOnTheBlades) {
  std::mt19937 rng(32);
  for (const models::BuiltModel& built : {DefaultModel("rotor"), UnequalTwoBladeRotor()}) {
    const int n = built.model.num_coordinates(), m = built.model.num_slots();
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, m);
    expected.topRows(m) = -Eigen::MatrixXd::Identity(m, m);
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
      const Eigen::MatrixXd B = CalcCouplingMatrix(built.model, 0.1 * trial, x);
      EXPECT_LT((B - expected).cwiseAbs().maxCoeff(), 1e-12) << B;
    }
  }
}

// J = ∂ẋ/∂x against central differences of CalcStateDerivative<double>. The pendulum and the
// top (no t-dependent loads) pass; the rotor fails from the engine bug above.
void ExpectJacobianMatchesCentralDifferences(const std::vector<std::string>& names) {
  std::mt19937 rng(33);
  for (const std::string& name : names) {
    const models::BuiltModel built = DefaultModel(name);
    const Model& model = built.model;
    const int nx = model.num_states();
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 3.0);
      const Eigen::VectorXd r = RandomForces(rng, model.num_slots(), 500.0);
      const double t = 0.4 * trial + 0.1;
      const Eigen::MatrixXd J = CalcStateJacobian(model, t, x, r);
      ASSERT_EQ(J.rows(), nx);
      ASSERT_EQ(J.cols(), nx);
      Eigen::MatrixXd fd(nx, nx);
      for (int k = 0; k < nx; ++k) {
        const double h = 1e-6 * std::max(1.0, std::abs(x(k)));
        Eigen::VectorXd xp = x, xm = x;
        xp(k) += h;
        xm(k) -= h;
        fd.col(k) = (test_support::StateDerivative(model, t, xp, r) -
                     test_support::StateDerivative(model, t, xm, r)) / (2 * h);
      }
      EXPECT_LT(RelativeError(J, fd), 1e-6) << name << " trial " << trial << "\nJ =\n"
                                            << J << "\nfd =\n" << fd;
    }
  }
}

TEST(DerivativesTest, StateJacobianMatchesCentralDifferences) {
  ExpectJacobianMatchesCentralDifferences({"double_pendulum", "spinning_top"});
}

// See the ENGINE BUG note above.
TEST(DerivativesTest, RotorStateJacobianMatchesCentralDifferences) {
  ExpectJacobianMatchesCentralDifferences({"rotor"});
}

// CalcStateDerivative<AutoDiff> carries the same values as the double instantiation.
TEST(DerivativesTest, AutoDiffValuesEqualDoubleValues) {
  std::mt19937 rng(34);
  for (const std::string& name : models::ModelNames()) {
    const models::BuiltModel built = DefaultModel(name);
    const Model& model = built.model;
    const int nx = model.num_states();
    Data<double> dd(model);
    Data<AutoDiff> da(model);
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd x = RandomState(rng, CoordinateScales(built), 5.0);
      const Eigen::VectorXd r = RandomForces(rng, model.num_slots(), 500.0);
      const double t = 0.3 * trial;
      Eigen::VectorXd xdot(nx);
      CalcStateDerivative<double>(model, dd, t, x, r, xdot);
      // Seed every state with a derivative direction, as CalcStateJacobian does.
      VectorX<AutoDiff> xa(nx), xdot_a(nx);
      for (int i = 0; i < nx; ++i) xa(i) = AutoDiff(x(i), Derivatives::Unit(nx, i));
      const VectorX<AutoDiff> ra = r.cast<AutoDiff>();
      CalcStateDerivative<AutoDiff>(model, da, AutoDiff(t), xa, ra, xdot_a);
      Eigen::VectorXd values(nx);
      for (int i = 0; i < nx; ++i) values(i) = xdot_a(i).value();
      EXPECT_LT(RelativeError(values, xdot), 1e-14) << name << " trial " << trial;
      Eigen::MatrixXd M_values(da.M.rows(), da.M.cols());
      for (Eigen::Index i = 0; i < M_values.size(); ++i) M_values(i) = da.M(i).value();
      EXPECT_LT(RelativeError(M_values, dd.M), 1e-14) << name;
    }
  }
}

}  // namespace
}  // namespace hybridtest::multibody
