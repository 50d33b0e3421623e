// The planar kernels (planar_kinematics.*): which models are planar, and that for doubles they
// give the general kernels' values exactly. The general kernels are reached through the
// AutoDiff instantiation (the planar path is for doubles only), whose value arithmetic is the
// same IEEE operations in the same order; the planar kernels skip exact zeros only, so every
// entry must be equal (0.0 == −0.0).
#include <gtest/gtest.h>

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

// A planar model about N's axis `axis` exercising every planar kernel: a driven hub (angle
// with a time rate), a constant-rotation frame, a hinge, a rigid body with a full inertia
// tensor and an offset along the axis, a slide with rate terms in two components (one along
// the axis), a point with a time-rate offset, forces and torques expressed in rotating
// frames, a slot. `tilt` turns the hinge about another axis: the model is then not planar.
Model BuildPlanar(int axis, bool tilt = false) {
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
  const int b = (axis + 1) % 3, d = (axis + 2) % 3;
  ModelBuilder builder({{"q1", "rad", ""}, {"q2", "rad", ""}, {"q3", "m", ""}});
  builder.AddTimeFunction("ramp", [](const auto& t) {
    using T = std::decay_t<decltype(t)>;
    using std::exp;
    return T(1.0 - exp(-t));
  });
  const FrameId H = builder.AddFrameAboutAxis("H", builder.newtonian(), e,
                                              ScalarField::Affine(0.3, {{0, 1.0}}, 0.7));
  builder.AddRigidBody("hub", H, builder.origin(), 0.0, Eigen::Vector3d(0.2, 0.3, 0.4).asDiagonal());
  const FrameId C = builder.AddFrameAboutAxis("C", H, e, ScalarField::Constant(2.1));
  const FrameId L = builder.AddFrameAboutAxis("L", C, tilt ? Eigen::Vector3d::Unit(b) : e,
                                              ScalarField::Coordinate(1, 1.5, -0.2));
  std::array<ScalarField, 3> pivot_at;
  pivot_at[b] = ScalarField::Constant(0.8);
  const PointId pivot = builder.AddPoint("pivot", builder.origin(), C, pivot_at);
  std::array<ScalarField, 3> g_at;
  g_at[b] = ScalarField::Constant(0.25);
  g_at[d] = ScalarField::Constant(-0.05);
  g_at[axis] = ScalarField::Constant(0.1);
  const PointId G = builder.AddPoint("G", pivot, L, g_at);
  Eigen::Matrix3d inertia;
  inertia << 0.03, 0.004, -0.002, 0.004, 0.05, 0.001, -0.002, 0.001, 0.04;
  builder.AddRigidBody("link", L, G, 1.3, inertia);
  std::array<ScalarField, 3> slide_at;
  slide_at[b] = ScalarField::Affine(0.4, {{2, 1.0}});
  slide_at[axis] = ScalarField::Affine(0.05, {{2, 0.5}});
  slide_at[d] = ScalarField::Affine(0.0, {}, 0.3);
  const PointId S = builder.AddPoint("S", G, L, slide_at);
  builder.AddParticle("slider", S, 0.7);
  builder.AddRestoringForceSlot("r1", "", ScalarField::Coordinate(2));
  builder.AddForce("spring", S, L, [b](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    Vector3<T> f(T(0.0), T(0.0), T(0.0));
    f(b) = -a.r[0] + 0.5 * a.u[2];
    return f;
  });
  builder.AddForce("gravity", G, builder.newtonian(), [d](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    Vector3<T> f(T(0.0), T(0.0), T(0.0));
    f(d) = T(-12.753) * a.time_function(0);
    return f;
  });
  builder.AddTorque("motor", H, C, [axis](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    Vector3<T> m(T(0.1), T(0.0), T(0.0));
    m(axis) = 2.0 - 0.3 * a.u[0];
    return m;
  });
  return std::move(builder).Build();
}

// ẋ, M and g for doubles (planar path) against the AutoDiff values (general path).
void ExpectPlanarMatchesGeneral(const Model& model) {
  const int n = model.num_coordinates();
  std::mt19937 rng(5);
  Data<double> data(model);
  Data<AutoDiff> data_ad(model);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 3.0), 4.0);
    const Eigen::VectorXd r = RandomForces(rng, model.num_slots(), 50.0);
    const double t = 0.37 * trial;
    Eigen::VectorXd xdot(model.num_states());
    CalcStateDerivative<double>(model, data, t, x, r, xdot);
    VectorX<AutoDiff> xdot_ad(model.num_states());
    CalcStateDerivative<AutoDiff>(model, data_ad, AutoDiff(t), x.cast<AutoDiff>(),
                                  r.cast<AutoDiff>(), xdot_ad);
    for (int i = 0; i < model.num_states(); ++i)
      EXPECT_EQ(xdot(i), xdot_ad(i).value()) << "trial " << trial << ", x'(" << i << ")";
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(data.g(i), data_ad.g(i).value()) << "trial " << trial << ", g(" << i << ")";
      for (int j = 0; j < n; ++j) EXPECT_EQ(data.M(i, j), data_ad.M(i, j).value());
    }
    // CalcStateDerivative leaves the velocities of the points; CalcKinematics computes them.
    CalcKinematics<double>(model, data, t, x);
    CalcKinematics<AutoDiff>(model, data_ad, AutoDiff(t), x.cast<AutoDiff>());
    for (std::size_t p = 0; p < model.points().size(); ++p) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(data.p_OP[p](c), data_ad.p_OP[p](c).value()) << "point " << p;
        EXPECT_EQ(data.v_NP[p](c), data_ad.v_NP[p](c).value()) << "point " << p;
        EXPECT_EQ(data.a_rem[p](c), data_ad.a_rem[p](c).value()) << "point " << p;
      }
    }
  }
}

// The right-hand side's kinematics (internal::CalcKinematics without positions) against the
// full CalcKinematics: every other result is the same, bit for bit, and p_OP and v_NP keep
// the values Data's constructor gave them (zero).
void ExpectOnlyPositionsSkipped(const Model& model) {
  const int n = model.num_coordinates();
  std::mt19937 rng(7);
  Data<double> full(model);
  Data<double> rhs(model);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 3.0), 4.0);
    const double t = 0.3 * trial;
    CalcKinematics<double>(model, full, t, x);
    internal::CalcKinematics<double>(model, rhs, t, x, false);
    for (std::size_t f = 0; f < model.frames().size(); ++f) {
      EXPECT_TRUE(rhs.R_NF[f] == full.R_NF[f]) << "frame " << f;
      EXPECT_TRUE(rhs.w_NF[f] == full.w_NF[f]) << "frame " << f;
      EXPECT_TRUE(rhs.w_partial[f] == full.w_partial[f]) << "frame " << f;
      EXPECT_TRUE(rhs.alpha_rem[f] == full.alpha_rem[f]) << "frame " << f;
    }
    for (std::size_t p = 1; p < model.points().size(); ++p) {
      EXPECT_TRUE(rhs.v_partial[p] == full.v_partial[p]) << "point " << p;
      EXPECT_TRUE(rhs.a_rem[p] == full.a_rem[p]) << "point " << p;
      EXPECT_TRUE(rhs.p_OP[p].isZero(0.0) && rhs.v_NP[p].isZero(0.0)) << "point " << p;
      EXPECT_FALSE(full.p_OP[p].isZero(0.0)) << "point " << p;
    }
  }
}

TEST(PlanarKinematics, RightHandSideSkipsOnlyThePointsPositionsAndVelocities) {
  ExpectOnlyPositionsSkipped(BuildPlanar(2));        // the planar kernels
  ExpectOnlyPositionsSkipped(BuildPlanar(1, true));  // the general affine kernel
}

TEST(PlanarKinematics, BuiltInModelsThatArePlanar) {
  EXPECT_EQ(DefaultModel("rotor").model.planar_axis(), 2);
  EXPECT_EQ(DefaultModel("double_pendulum").model.planar_axis(), 2);
  EXPECT_EQ(DefaultModel("spinning_top").model.planar_axis(), -1);  // q̇ = W(q) u, 3-D
}

TEST(PlanarKinematics, DetectsTheAxisAndRejectsATiltedHinge) {
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_EQ(BuildPlanar(axis).planar_axis(), axis);
    EXPECT_EQ(BuildPlanar(axis, true).planar_axis(), -1);
  }
}

TEST(PlanarKinematics, DoublesEqualTheGeneralKernelsAboutEveryAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    ExpectPlanarMatchesGeneral(BuildPlanar(axis));
  }
}

TEST(PlanarKinematics, BuiltInModelsEqualTheGeneralKernels) {
  ExpectPlanarMatchesGeneral(DefaultModel("rotor").model);
  ExpectPlanarMatchesGeneral(DefaultModel("double_pendulum").model);
}

}  // namespace
}  // namespace hybridtest::multibody
