// The constant entries of a planar model's mass matrix and the factor columns that follow from
// them (constant_mass.*): which entries are constant, their values, and that M and ẋ agree with
// an independent assembly from the partial velocities and a dense LLT solve at random states.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <array>
#include <cmath>
#include <random>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::DefaultModel;
using test_support::RandomForces;
using test_support::RandomState;

// A planar model with two slides whose frames keep a constant relative angle (C and D hang
// from the hub at 0.9 and −0.4 rad) and a hinge carrying a rigid body: M_11, M_22, M_12
// (sin 1.3 couples the slides) and M_33 are constant; the hub's entries and a slide against
// the hinge are not.
Model BuildSlides() {
  ModelBuilder b({{"q0", "rad", ""}, {"q1", "m", ""}, {"q2", "m", ""}, {"q3", "rad", ""}});
  const FrameId H = b.AddFrameAboutAxis("H", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                        ScalarField::Coordinate(0));
  b.AddRigidBody("hub", H, b.origin(), 0.0, Eigen::Vector3d(0.1, 0.1, 2.0).asDiagonal());
  const FrameId C = b.AddFrameAboutAxis("C", H, Eigen::Vector3d::UnitZ(), ScalarField::Constant(0.9));
  const FrameId D = b.AddFrameAboutAxis("D", H, Eigen::Vector3d::UnitZ(), ScalarField::Constant(-0.4));
  const PointId P1 = b.AddPoint("P1", b.origin(), C,
                                {ScalarField::Constant(0.5), ScalarField::Coordinate(1), {}});
  b.AddParticle("m1", P1, 1.7);
  const PointId P2 = b.AddPoint("P2", P1, D,
                                {ScalarField::Affine(0.3, {{2, 1.0}}), ScalarField::Constant(0.1), {}});
  b.AddParticle("m2", P2, 0.6);
  const FrameId L = b.AddFrameAboutAxis("L", D, Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(3));
  const PointId G = b.AddPoint("G", P2, L, {ScalarField::Constant(0.4), {}, {}});
  b.AddRigidBody("link", L, G, 0.9, Eigen::Vector3d(0.01, 0.02, 0.03).asDiagonal());
  b.AddForce("push", P2, D, [](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return Vector3<T>(T(-3.0) * a.q[2], T(0.5) * a.u[0], T(0.0));
  });
  return std::move(b).Build();
}

// M = Σ m V_jᵀ V_k + Σ ω_jᵀ R I Rᵀ ω_k from the kinematics' partial velocities.
Eigen::MatrixXd IndependentMassMatrix(const Model& model, const Data<double>& data) {
  const int n = model.num_coordinates();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  auto point_mass = [&](int p, double m) {
    const Eigen::Matrix3Xd& V = data.v_partial[p];
    M += m * V.transpose() * V;
  };
  for (const ParticleSpec& pa : model.particles()) point_mass(pa.point, pa.mass);
  for (const RigidBodySpec& body : model.bodies()) {
    if (body.mass > 0.0) point_mass(body.mass_center, body.mass);
    const Eigen::Matrix3d& R = data.R_NF[body.frame];
    const Eigen::Matrix3Xd& W = data.w_partial[body.frame];
    M += W.transpose() * (R * body.inertia * R.transpose()) * W;
  }
  return M;
}

void ExpectAgreesWithIndependentAssembly(const Model& model) {
  const int n = model.num_coordinates();
  std::mt19937 rng(11);
  Data<double> data(model);
  Eigen::VectorXd xdot(model.num_states());
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 2.0), 3.0);
    const Eigen::VectorXd r = RandomForces(rng, model.num_slots(), 100.0);
    CalcStateDerivative<double>(model, data, 0.3 * trial, x, r, xdot);
    const Eigen::MatrixXd M = IndependentMassMatrix(model, data);
    const double scale = M.cwiseAbs().maxCoeff();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        EXPECT_NEAR(data.M(i, j), M(i, j), 1e-13 * scale) << "trial " << trial << " M(" << i
                                                          << ", " << j << ")";
    const Eigen::VectorXd udot = M.llt().solve(data.g);
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(xdot(n + i), udot(i), 1e-11 * std::max(1.0, udot.cwiseAbs().maxCoeff()))
          << "trial " << trial << " u'(" << i << ")";
  }
}

TEST(ConstantMass, RotorBladeEntriesAreConstantAndExact) {
  const models::BuiltModel built = DefaultModel("rotor");
  const ConstantMassPlan& plan = built.model.constant_mass();
  ASSERT_EQ(plan.entry.size(), 16u);
  const double m_b = built.parameters.Get("m_b"), l_b = built.parameters.Get("l_b");
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(plan.entry[i + 4 * i]);
    EXPECT_EQ(plan.value[i + 4 * i], m_b);  // m·(ŷ·ŷ), not m(c² + s²)
    EXPECT_TRUE(plan.entry[3 + 4 * i]);
    EXPECT_TRUE(plan.entry[i + 4 * 3]);
    EXPECT_EQ(plan.value[3 + 4 * i], m_b * l_b);
    EXPECT_TRUE(plan.factor_column[i]);  // the blades' columns of L
  }
  EXPECT_FALSE(plan.entry[15]);  // I_g + Σ m (l² + q_i²)
  EXPECT_FALSE(plan.factor_column[3]);
}

TEST(ConstantMass, SlidesInFramesAtAConstantAngle) {
  const Model model = BuildSlides();
  const ConstantMassPlan& plan = model.constant_mass();
  ASSERT_EQ(plan.entry.size(), 16u);
  EXPECT_TRUE(plan.entry[1 + 4 * 1]);
  EXPECT_TRUE(plan.entry[2 + 4 * 2]);
  EXPECT_TRUE(plan.entry[1 + 4 * 2]);
  EXPECT_NEAR(plan.value[1 + 4 * 2], (0.6 + 0.9) * std::cos(1.3 + M_PI / 2.0), 1e-15);
  EXPECT_FALSE(plan.entry[0]);          // the hub: |p|² varies
  EXPECT_TRUE(plan.entry[3 + 4 * 3]);   // the hinge: G at a fixed distance, m r² + I_zz
  EXPECT_NEAR(plan.value[3 + 4 * 3], 0.9 * 0.16 + 0.03, 1e-15);
  EXPECT_FALSE(plan.entry[1 + 4 * 3]);  // a slide against the hinge: cos q3
  ExpectAgreesWithIndependentAssembly(model);
}

TEST(ConstantMass, PlanarModelsAgreeWithAnIndependentAssembly) {
  ExpectAgreesWithIndependentAssembly(DefaultModel("rotor").model);
  ExpectAgreesWithIndependentAssembly(DefaultModel("double_pendulum").model);
}

TEST(ConstantMass, OnlyPlanarModels) {
  EXPECT_TRUE(DefaultModel("spinning_top").model.constant_mass().entry.empty());  // W(q), 3-D
}

}  // namespace
}  // namespace hybridtest::multibody
