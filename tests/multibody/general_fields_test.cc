// General kinematic fields (ScalarField::Function lambdas, differentiated on jets) give the same
// M, g and ẋ as the affine fast path (ScalarField::Coordinate/Constant/Affine) for the same
// expressions. Two models: the paper's rotor, and a pendulum on a base spun at a prescribed
// rate (time-dependent angle), which the rotor does not exercise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::RandomForces;
using test_support::RandomState;
using test_support::RelativeError;

// A constant as a general field.
ScalarField GeneralConstant(double c) {
  return ScalarField::Function([c](const auto& a) { return decltype(a.t)(c); });
}
// c0 + Σ c_k q_k + c_t t as a general field.
ScalarField GeneralAffine(double c0, std::vector<ScalarField::Term> terms, double rate = 0.0) {
  return ScalarField::Function([=](const auto& a) {
    auto v = decltype(a.t)(c0) + rate * a.t;
    for (const auto& term : terms) v = v + term.coefficient * a.q[term.coordinate];
    return v;
  });
}

// The rotor of rotor.h (3 blades, Table 1), with every field affine or every field general.
Model BuildRotor(bool general) {
  constexpr int N = 3;
  constexpr double l_b = 0.5, m_b = 1.96, c = 1.96, f_w = 100.0, I_g = 0.1, d_g = 100.0,
                   G = 9.82, t0 = 0.5;
  auto coordinate = [&](int k) {
    return general ? GeneralAffine(0.0, {{k, 1.0}}) : ScalarField::Coordinate(k);
  };
  auto constant = [&](double v) { return general ? GeneralConstant(v) : ScalarField::Constant(v); };
  ModelBuilder b({{"q1", "m", ""}, {"q2", "m", ""}, {"q3", "m", ""}, {"q4", "rad", ""}});
  const FrameId H = b.AddFrameAboutAxis("H", b.newtonian(), Eigen::Vector3d::UnitZ(), coordinate(3));
  b.AddRigidBody("hub", H, b.origin(), 0.0, Eigen::Vector3d(0, 0, I_g).asDiagonal());
  for (int i = 0; i < N; ++i) {
    const FrameId B = b.AddFrameAboutAxis("B", H, Eigen::Vector3d::UnitZ(),
                                          constant(2 * std::numbers::pi * i / N));
    const PointId P = b.AddPoint("P", b.origin(), B, {constant(l_b), coordinate(i), constant(0.0)});
    b.AddParticle("tip", P, m_b);
    b.AddRestoringForceSlot("r" + std::to_string(i + 1), "", coordinate(i));
    b.AddForce("blade", P, B, [=](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      using std::exp;
      const T ramp = 1.0 - exp(-a.t / t0);
      return Vector3<T>(T(0.0), -(a.r[i] + c * a.u[i]) + ramp * f_w, T(0.0));
    });
    b.AddForce("gravity", P, b.newtonian(), [=](const auto& a) {
      using T = std::decay_t<decltype(a.t)>;
      using std::exp;
      return Vector3<T>(m_b * G * (1.0 - exp(-a.t / t0)), T(0.0), T(0.0));
    });
  }
  b.AddTorque("hub", H, b.newtonian(), [=](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    T tz = -d_g * a.u[3];
    for (int i = 0; i < N; ++i) tz += (a.r[i] + c * a.u[i]) * l_b;
    return Vector3<T>(T(0.0), T(0.0), tz);
  });
  return std::move(b).Build();
}

// A pendulum hanging from a base S spun about n̂_z at a prescribed angle 0.3 + 0.7 t; the
// pendulum frame A swings about ŝ_x by q1, and the bob slides along the rod: P = O +
// (0.2, 0.1 q2 − 0.05 t, −(1 + 0.5 q2)) in A. Gravity −m g n̂_z.
Model BuildSpunPendulum(bool general) {
  ModelBuilder b({{"q1", "rad", ""}, {"q2", "m", ""}});
  const ScalarField spin = general ? GeneralAffine(0.3, {}, 0.7) : ScalarField::Affine(0.3, {}, 0.7);
  const FrameId S = b.AddFrameAboutAxis("S", b.newtonian(), Eigen::Vector3d::UnitZ(), spin);
  const FrameId A = b.AddFrameAboutAxis(
      "A", S, Eigen::Vector3d::UnitX(),
      general ? GeneralAffine(0.0, {{0, 1.0}}) : ScalarField::Coordinate(0));
  std::array<ScalarField, 3> p;
  if (general) {
    p = {GeneralConstant(0.2), GeneralAffine(0.0, {{1, 0.1}}, -0.05),
         GeneralAffine(-1.0, {{1, -0.5}})};
  } else {
    p = {ScalarField::Constant(0.2), ScalarField::Affine(0.0, {{1, 0.1}}, -0.05),
         ScalarField::Affine(-1.0, {{1, -0.5}})};
  }
  const PointId P = b.AddPoint("P", b.origin(), A, p);
  b.AddParticle("bob", P, 0.8);
  b.AddRigidBody("rod", A, P, 0.0, Eigen::Vector3d(0.01, 0.02, 0.005).asDiagonal());
  b.AddForce("gravity", P, b.newtonian(), [](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return Vector3<T>(T(0.0), T(0.0), T(-0.8 * 9.81));
  });
  return std::move(b).Build();
}

void ExpectSameDynamics(const Model& affine, const Model& general, const Eigen::VectorXd& q_scale,
                        unsigned seed) {
  ASSERT_FALSE(affine.has_general_fields());
  ASSERT_TRUE(general.has_general_fields());
  std::mt19937 rng(seed);
  Data<double> da(affine), dg(general);
  const int nx = affine.num_states();
  for (int trial = 0; trial < 25; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, q_scale, 4.0);
    const Eigen::VectorXd r = RandomForces(rng, affine.num_slots(), 500.0);
    const double t = 0.2 * trial;
    Eigen::VectorXd xa(nx), xg(nx);
    CalcStateDerivative<double>(affine, da, t, x, r, xa);
    CalcStateDerivative<double>(general, dg, t, x, r, xg);
    EXPECT_LT(RelativeError(dg.M, da.M), 1e-12) << "trial " << trial;
    EXPECT_LT(RelativeError(dg.g, da.g), 1e-12) << "trial " << trial;
    EXPECT_LT(RelativeError(xg, xa), 1e-12) << "trial " << trial;
    // Slot displacements agree too.
    Eigen::VectorXd sa(affine.num_slots()), sg(general.num_slots());
    CalcSlotDisplacements<double>(affine, da, t, x.head(nx / 2), sa);
    CalcSlotDisplacements<double>(general, dg, t, x.head(nx / 2), sg);
    EXPECT_LT(RelativeError(sg, sa), 1e-15);
  }
}

TEST(GeneralFieldsTest, RotorWithLambdaFieldsEqualsAffineRotor) {
  Eigen::VectorXd scale(4);
  scale << 0.05, 0.05, 0.05, 3.0;
  ExpectSameDynamics(BuildRotor(false), BuildRotor(true), scale, 3);
}

TEST(GeneralFieldsTest, TimeDependentFieldsEqualAffineTimeRates) {
  ExpectSameDynamics(BuildSpunPendulum(false), BuildSpunPendulum(true), Eigen::Vector2d(3.0, 0.5),
                     4);
}

// Positive control for the comparison: a general field that differs slightly (the rod sliding
// at −0.06 t instead of −0.05 t) is detected.
TEST(GeneralFieldsTest, ComparisonDetectsADifferentField) {
  const Model affine = BuildSpunPendulum(false);
  ModelBuilder b({{"q1", "rad", ""}, {"q2", "m", ""}});
  const FrameId S = b.AddFrameAboutAxis("S", b.newtonian(), Eigen::Vector3d::UnitZ(),
                                        GeneralAffine(0.3, {}, 0.7));
  const FrameId A =
      b.AddFrameAboutAxis("A", S, Eigen::Vector3d::UnitX(), GeneralAffine(0.0, {{0, 1.0}}));
  const PointId P = b.AddPoint("P", b.origin(), A,
                               {GeneralConstant(0.2), GeneralAffine(0.0, {{1, 0.1}}, -0.06),
                                GeneralAffine(-1.0, {{1, -0.5}})});
  b.AddParticle("bob", P, 0.8);
  b.AddRigidBody("rod", A, P, 0.0, Eigen::Vector3d(0.01, 0.02, 0.005).asDiagonal());
  b.AddForce("gravity", P, b.newtonian(), [](const auto& a) {
    using T = std::decay_t<decltype(a.t)>;
    return Vector3<T>(T(0.0), T(0.0), T(-0.8 * 9.81));
  });
  const Model other = std::move(b).Build();
  const Eigen::VectorXd x = (Eigen::VectorXd(4) << 0.4, 0.1, 1.0, -0.5).finished();
  const Eigen::VectorXd r(0);
  EXPECT_GT(RelativeError(test_support::StateDerivative(other, 1.0, x, r),
                          test_support::StateDerivative(affine, 1.0, x, r)),
            1e-6);
}

}  // namespace
}  // namespace hybridtest::multibody
