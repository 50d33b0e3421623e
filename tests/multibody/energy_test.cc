// Energy conservation of the conservative built-in models under RK4 (integrators::
// ExplicitRungeKutta + CalcStateDerivative): tiny drift at a small step, and a drift that falls
// by about 2⁴ = 16 when the step is halved (fourth order). A wrong Coriolis/centrifugal or
// gyroscopic term in g breaks conservation at first order and fails both.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using EnergyFn = std::function<double(const Data<double>&)>;

// Double pendulum (double_pendulum.h): E = ½ Σ m_i |v_i|² − g Σ m_i x_i, points P1 = 1, P2 = 2.
EnergyFn PendulumEnergy(const models::ParameterSet& p) {
  const double m1 = p.Get("m1"), m2 = p.Get("m2"), g = p.Get("g");
  return [=](const Data<double>& d) {
    return 0.5 * m1 * d.v_NP[1].squaredNorm() + 0.5 * m2 * d.v_NP[2].squaredNorm() -
           g * (m1 * d.p_OP[1].x() + m2 * d.p_OP[2].x());
  };
}

// Spinning top (spinning_top.h): E = ½ m |v_G|² + ½ uᵀ I_G u + m g z_G, G = point 1, u = ω in C.
EnergyFn TopEnergy(const models::ParameterSet& p) {
  const double m = p.Get("m"), g = p.Get("g");
  Eigen::Matrix3d I;
  I << p.Get("Ixx"), p.Get("Ixy"), p.Get("Ixz"), p.Get("Ixy"), p.Get("Iyy"), p.Get("Iyz"),
      p.Get("Ixz"), p.Get("Iyz"), p.Get("Izz");
  return [=](const Data<double>& d) {
    const Eigen::Vector3d w = d.u;
    return 0.5 * m * d.v_NP[1].squaredNorm() + 0.5 * w.dot(I * w) + m * g * d.p_OP[1].z();
  };
}

// Largest |E(t) − E(0)| / |E(0)| over an RK4 run of `duration` seconds with step h.
double RelativeEnergyDrift(const models::BuiltModel& built, const EnergyFn& energy,
                           const Eigen::VectorXd& x0, double h, double duration) {
  const Model& model = built.model;
  Data<double> data(model);
  const Eigen::VectorXd r(0);
  integrators::ExplicitRungeKutta rk4(integrators::FindTableau("rk4"), model.num_states());
  auto stage = [&](int, double t, const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> k) {
    CalcStateDerivative<double>(model, data, t, x, r, k);
  };
  auto energy_at = [&](const Eigen::VectorXd& x) {
    CalcKinematics<double>(model, data, 0.0, x);
    return energy(data);
  };
  const double e0 = energy_at(x0);
  Eigen::VectorXd x = x0, x_next(x0.size());
  const long steps = std::lround(duration / h);
  double drift = 0.0;
  for (long n = 0; n < steps; ++n) {
    rk4.Step(static_cast<double>(n) * h, h, x, stage, x_next);
    x.swap(x_next);
    drift = std::max(drift, std::abs(energy_at(x) - e0));
  }
  return drift / std::abs(e0);
}

struct Case {
  const char* model;
  Eigen::VectorXd x0;
};

std::vector<Case> Cases() {
  Eigen::VectorXd pendulum(4), top(6);
  pendulum << 1.0, -0.5, 0.5, 1.0;
  top << 0.2, -0.3, 0.4, 1.0, -0.5, 8.0;
  // Moved, not copied: GCC 12 at -O1 misreads a copy of a fresh VectorXd
  // (-Wmaybe-uninitialized inside Eigen's DenseStorage).
  std::vector<Case> cases;
  cases.push_back({"double_pendulum", std::move(pendulum)});
  cases.push_back({"spinning_top", std::move(top)});
  return cases;
}

EnergyFn EnergyOf(const models::BuiltModel& built) {
  return built.name == "double_pendulum" ? PendulumEnergy(built.parameters)
                                         : TopEnergy(built.parameters);
}

TEST(EnergyTest, Rk4ConservesEnergyAtSmallStep) {
  for (const Case& c : Cases()) {
    const models::BuiltModel built = test_support::DefaultModel(c.model);
    const double drift = RelativeEnergyDrift(built, EnergyOf(built), c.x0, 1e-3, 3.0);
    EXPECT_LT(drift, 1e-9) << c.model;
    RecordProperty(std::string(c.model) + "_drift_h1ms", std::to_string(drift));
  }
}

TEST(EnergyTest, EnergyDriftIsFourthOrderInTheStep) {
  for (const Case& c : Cases()) {
    const models::BuiltModel built = test_support::DefaultModel(c.model);
    const double coarse = RelativeEnergyDrift(built, EnergyOf(built), c.x0, 0.01, 3.0);
    const double fine = RelativeEnergyDrift(built, EnergyOf(built), c.x0, 0.005, 3.0);
    ASSERT_GT(fine, 1e-11) << c.model << ": drift too small to measure an order";
    const double ratio = coarse / fine;
    std::printf("%s: energy drift %.3g (h = 10 ms), %.3g (h = 5 ms), ratio %.2f\n", c.model,
                coarse, fine, ratio);
    EXPECT_GT(ratio, 12.0) << c.model;
    EXPECT_LT(ratio, 40.0) << c.model;  // between 2⁴ and 2⁵ (oscillatory drift can be O(h⁵))
  }
}

}  // namespace
}  // namespace hybridtest::multibody
