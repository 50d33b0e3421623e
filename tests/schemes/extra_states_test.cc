// Extra first-order states (x = [q; u; z]) through every hybrid scheme: a forced oscillator
// whose spring is the specimen behind the seam, with an integral feedback force −K_i z,
// ż = q − z/τ. Each scheme converges on q and z to a fine Runge–Kutta reference at its order,
// and continues bit-identically after SaveState/RestoreState.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/schemes/scheme_config.h"
#include "schemes/oscillator.h"

namespace hybridtest::schemes {
namespace {

using testing::CollectRows;
using testing::SpringSeam;

constexpr double kEnd = 1.0;      // [s]
constexpr double kStiffness = 800.0;  // [N/m] specimen

multibody::Model ModelWithIntegrator() {
  using multibody::ScalarField;
  multibody::ModelBuilder b({{"q1", "m", "displacement"}});
  const auto P = b.AddPoint("P", b.origin(), b.newtonian(), {ScalarField::Coordinate(0), {}, {}});
  b.AddParticle("mass", P, 2.0);
  b.AddRestoringForceSlot("r1", "spring", ScalarField::Coordinate(0));
  b.AddExtraState({"z", "m·s", "integral of q, leaking"}, 0.0, [](const auto& a) {
    return a.q[0] - 2.0 * a.z[0];
  });
  b.AddForce("spring, damper, forcing, integral", P, b.newtonian(), [](const auto& a) {
    using T = std::decay_t<decltype(a.u[0])>;
    return multibody::Vector3<T>(-a.r[0] - 0.6 * a.u[0] + 5.0 * sin(7.0 * a.t) - 300.0 * a.z[0],
                                 T(0.0), T(0.0));
  });
  return std::move(b).Build();
}

SchemeConfig Config(SchemeKind kind) {
  SchemeConfig c;
  c.kind = kind;
  c.substep = 1e-4;
  return c;
}

// The committed state at kEnd; with `stop_after` > 0 the scheme is saved, destroyed and
// restored after that many steps.
Eigen::VectorXd Integrate(const SchemeConfig& c, double h, double k0, long stop_after = 0) {
  const multibody::Model model = ModelWithIntegrator();
  EXPECT_EQ(model.num_states(), 3);
  SlotInfo slots{Eigen::VectorXd::Constant(1, k0),
                 Eigen::VectorXd::Constant(1, std::numeric_limits<double>::infinity()),
                 Eigen::MatrixXd()};
  const long steps = std::lround(kEnd / h);
  auto make = [&] {
    return MakeScheme(c, integrators::FindTableau("rk4"), h, kEnd, steps, model, slots);
  };
  auto scheme = make();
  SpringSeam seam(kStiffness);
  CollectRows rows;
  Eigen::VectorXd x0(3), r0(1);
  x0 << 0.01, 0.0, 0.002;
  seam.Trial({0, 0, 0.0}, x0.head(1), r0);
  scheme->Start(0.0, x0, r0);
  while (!scheme->finished()) {
    scheme->Step(seam, rows);
    if (stop_after > 0 && scheme->committed().step == stop_after) {
      const std::string saved = scheme->SaveState().dump();
      scheme = make();
      scheme->RestoreState(nlohmann::json::parse(saved));
    }
  }
  return scheme->committed().x;
}

// Order observed on q and on z: log2 of the error ratio when h is halved (at t = kEnd only, so
// the errors' phase can make it look higher than it is; a lower order is a failure).
Eigen::Vector2d Order(const SchemeConfig& c, double h, double k0) {
  const Eigen::VectorXd ref = Integrate(Config(SchemeKind::kRungeKutta), 1e-5, kStiffness);
  const Eigen::VectorXd e1 = (Integrate(c, h, k0) - ref).cwiseAbs();
  const Eigen::VectorXd e2 = (Integrate(c, h / 2, k0) - ref).cwiseAbs();
  return {std::log2(e1(0) / e2(0)), std::log2(e1(2) / e2(2))};
}

TEST(ExtraStates, RungeKuttaIntegratesThemAtItsOrder) {
  const Eigen::Vector2d p = Order(Config(SchemeKind::kRungeKutta), 0.02, kStiffness);
  EXPECT_NEAR(p(0), 4.0, 0.3);
  EXPECT_GT(p(1), 3.7);
}

TEST(ExtraStates, AlphaOsIntegratesThemAtSecondOrderWithExactAndSoftK0) {
  for (double k0 : {kStiffness, 0.6 * kStiffness}) {
    const Eigen::Vector2d p = Order(Config(SchemeKind::kAlphaOs), 0.01, k0);
    EXPECT_NEAR(p(0), 2.0, 0.25) << "K0 = " << k0;
    EXPECT_GT(p(1), 1.75) << "K0 = " << k0;
  }
}

TEST(ExtraStates, MrOsIntegratesThem) {
  // K0 = the specimen's stiffness: exact up to the RK4 substeps.
  const Eigen::VectorXd ref = Integrate(Config(SchemeKind::kRungeKutta), 1e-5, kStiffness);
  EXPECT_LT((Integrate(Config(SchemeKind::kMrOs), 0.05, kStiffness) - ref).cwiseAbs().maxCoeff(),
            1e-11);
  const Eigen::Vector2d p = Order(Config(SchemeKind::kMrOs), 0.02, 0.6 * kStiffness);
  EXPECT_GT(p(0), 1.8);
  EXPECT_GT(p(1), 1.8);
}

TEST(ExtraStates, SchemesContinueBitIdenticallyAfterRestore) {
  for (SchemeKind kind : {SchemeKind::kRungeKutta, SchemeKind::kAlphaOs, SchemeKind::kMrOs}) {
    const Eigen::VectorXd a = Integrate(Config(kind), 0.01, 0.6 * kStiffness);
    const Eigen::VectorXd b = Integrate(Config(kind), 0.01, 0.6 * kStiffness, 37);
    EXPECT_EQ(a, b) << SchemeKindName(kind);
  }
}

// The exact Jacobian (AutoDiff) has the extra state's rows and columns.
TEST(ExtraStates, StateJacobianCoversThem) {
  const multibody::Model model = ModelWithIntegrator();
  Eigen::VectorXd x(3), r(1);
  x << 0.3, -0.2, 0.05;
  r << 7.0;
  const Eigen::MatrixXd J = multibody::CalcStateJacobian(model, 0.1, x, r);
  EXPECT_DOUBLE_EQ(J(1, 2), -300.0 / 2.0);  // ∂u̇/∂z = −K_i / m
  EXPECT_DOUBLE_EQ(J(2, 0), 1.0);           // ∂ż/∂q
  EXPECT_DOUBLE_EQ(J(2, 2), -2.0);          // ∂ż/∂z
  EXPECT_DOUBLE_EQ(J(2, 1), 0.0);
}

}  // namespace
}  // namespace hybridtest::schemes
