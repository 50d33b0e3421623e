// The rotor in time: the hub's steady speed from the torque balance N f_w l_b = d_g u_hub
// (PAPER-NOTES), and the stability limit of Heun's method set by the linearized model's
// fastest real eigenvalue (≈ −958 1/s, from the generator damping on the collective
// blade–hub mode). Numerical blades: r_i^s = k_b q_i.
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

// Heun from the zero state with numerical blades; returns the final state, or stops early
// (returning the state reached) once |x|∞ exceeds `blow_up` or is not finite.
Eigen::VectorXd SimulateHeun(const models::BuiltModel& built, double h, double duration,
                             double blow_up = 1e6) {
  const Model& model = built.model;
  const int n = model.num_coordinates();
  Data<double> data(model);
  Eigen::VectorXd d(model.num_slots()), r(model.num_slots());
  const Eigen::Map<const Eigen::VectorXd> k(built.slot_stiffness.data(), model.num_slots());
  integrators::ExplicitRungeKutta heun(integrators::FindTableau("heun"), model.num_states());
  auto stage = [&](int, double t, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> xdot) {
    CalcSlotDisplacements<double>(model, data, t, x.head(n), d);
    r = k.cwiseProduct(d);
    CalcStateDerivative<double>(model, data, t, x, r, xdot);
  };
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_states()), x_next(x.size());
  const long steps = std::lround(duration / h);
  for (long s = 0; s < steps; ++s) {
    heun.Step(static_cast<double>(s) * h, h, x, stage, x_next);
    x.swap(x_next);
    if (!x.allFinite() || x.cwiseAbs().maxCoeff() > blow_up) break;
  }
  return x;
}

TEST(RotorDynamicsTest, HubReachesTheTorqueBalanceSpeed) {
  const models::BuiltModel rotor = test_support::DefaultModel("rotor");
  const Eigen::VectorXd x = SimulateHeun(rotor, 1e-3, 10.0);
  const double expected = 3 * 100.0 * 0.5 / 100.0;  // 3 f_w l_b / d_g = 1.5 rad/s
  EXPECT_NEAR(x(7), expected, 1e-3);
}

TEST(RotorDynamicsTest, SteadySpeedScalesWithBladesAndWind) {
  models::ParameterSet p = models::DefaultParameters("rotor", 4);
  p.Set("f_w", 60.0, "test");
  const models::BuiltModel rotor = models::BuildModel("rotor", 4, p);
  const Eigen::VectorXd x = SimulateHeun(rotor, 1e-3, 10.0);
  EXPECT_NEAR(x(9), 4 * 60.0 * 0.5 / 100.0, 1e-3);  // N f_w l_b / d_g = 1.2 rad/s
}

// Linearization with numerical blades (r = k_b q) at the zero state, late (ramps = 1), by
// central differences of the double engine (independent of the AutoDiff path, which
// derivatives_test.cc checks against the same differences).
Eigen::MatrixXd ClosedLoopJacobian(const models::BuiltModel& built, double t) {
  const Model& model = built.model;
  const int n = model.num_coordinates(), m = model.num_slots(), nx = 2 * n;
  auto rhs = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd r(m);
    for (int s = 0; s < m; ++s) r(s) = built.slot_stiffness[s] * x(s);  // slot s sees q_s
    return test_support::StateDerivative(model, t, x, r);
  };
  Eigen::MatrixXd J(nx, nx);
  const double h = 1e-7;
  for (int k = 0; k < nx; ++k) {
    Eigen::VectorXd xp = Eigen::VectorXd::Zero(nx), xm = xp;
    xp(k) = h;
    xm(k) = -h;
    J.col(k) = (rhs(xp) - rhs(xm)) / (2 * h);
  }
  return J;
}

TEST(RotorDynamicsTest, LinearizedRotorHasTheFastRealEigenvalue) {
  const models::BuiltModel rotor = test_support::DefaultModel("rotor");
  const Eigen::MatrixXd J = ClosedLoopJacobian(rotor, 50.0);
  const Eigen::VectorXcd eig = J.eigenvalues();
  double fastest = 0.0;
  for (const auto& l : eig) {
    if (std::abs(l.imag()) < 1e-9 && l.real() < fastest) fastest = l.real();
  }
  std::printf("fastest real eigenvalue %.2f 1/s; Heun limit 2/|λ| = %.3f ms\n", fastest,
              2e3 / -fastest);
  EXPECT_NEAR(fastest, -958.0, 5.0);
  // Heun on ẏ = λy is stable iff |1 + z + z²/2| ≤ 1, i.e. z = hλ ∈ [−2, 0].
  const double h_limit = 2.0 / -fastest;
  EXPECT_NEAR(h_limit, 2.1e-3, 0.05e-3);
}

// Above the limit the fast mode grows at |1 + z + z²/2| ≈ 1.22 per step, but it does not
// diverge to infinity: the growing tip deflections raise the hub's effective inertia
// I_g + Σ m_b q_i² (the Schur complement of the arrow matrix), which lowers |λ| below 2/h, and
// the solution settles into a spurious oscillation with hub speeds ≈ 40 rad/s (the physical
// value is 1.5 rad/s) and blade speeds ≈ 18 m/s. "Blows up" is therefore asserted as leaving
// the physical range by an order of magnitude.
TEST(RotorDynamicsTest, HeunIsUnstableJustAboveTheLimitAndStableJustBelow) {
  const models::BuiltModel rotor = test_support::DefaultModel("rotor");
  const Eigen::VectorXd unstable = SimulateHeun(rotor, 2.3e-3, 3.0, 1e3);
  EXPECT_TRUE(!unstable.allFinite() || std::abs(unstable(7)) > 15.0) << unstable.transpose();
  EXPECT_TRUE(!unstable.allFinite() || unstable.segment(4, 3).cwiseAbs().maxCoeff() > 5.0)
      << unstable.transpose();
  const Eigen::VectorXd stable = SimulateHeun(rotor, 1.9e-3, 3.0, 1e3);
  ASSERT_TRUE(stable.allFinite());
  EXPECT_LT(stable.head(3).cwiseAbs().maxCoeff(), 0.1) << stable.transpose();      // tips [m]
  EXPECT_LT(stable.segment(4, 3).cwiseAbs().maxCoeff(), 0.5) << stable.transpose();  // [m/s]
  EXPECT_NEAR(stable(7), 1.5, 0.05) << stable.transpose();                         // hub [rad/s]
}

}  // namespace
}  // namespace hybridtest::multibody
