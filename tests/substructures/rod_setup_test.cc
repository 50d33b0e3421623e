// RodSetup (large-displacement geometry): J(d) against finite differences of the rod lengths,
// r = J(d)ᵀ f against the gradient of the potential ½ Δℓᵀ K_a Δℓ (and its tangent against the
// geometric stiffness), the small-displacement limit against the linear setup T = J(0), the
// step bound, the singularity scan and the geometry's validation. The oracles compute the rod
// lengths from the points directly, not through RodSetup.
#include "hybridtest/substructures/rod_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {
namespace {

// Three rods in 3-D on two slots, one direction not a unit vector, no symmetry.
RodGeometry ThreeRods() {
  RodGeometry g;
  g.directions.resize(3, 2);
  g.directions << 1.0, 0.1,
                  0.0, 0.9,
                  0.2, -0.3;
  g.bases.resize(3, 3);
  g.attachments.resize(3, 3);
  g.bases << -0.5, 0.1, -0.2,
              0.05, -0.45, -0.3,
              0.1, 0.2, 0.35;
  g.attachments << 0.0, 0.02, -0.01,
                   0.01, 0.0, 0.03,
                   0.0, -0.02, 0.05;
  g.p0 = Eigen::Vector3d(0.02, 0.03, -0.01);
  g.load_cell_zero = Eigen::Vector3d::Zero();
  return g;
}

// The oracle's rod lengths: |c_k + Σ d_i e_i − b_k|, from the raw points.
Eigen::VectorXd Lengths(const RodGeometry& g, const Eigen::VectorXd& d) {
  Eigen::VectorXd l(g.bases.cols());
  for (Eigen::Index k = 0; k < l.size(); ++k) {
    Eigen::VectorXd p = g.attachments.col(k) - g.bases.col(k);
    for (Eigen::Index i = 0; i < d.size(); ++i) p += d(i) * g.directions.col(i);
    l(k) = std::sqrt(p.dot(p));
  }
  return l;
}

std::vector<Eigen::VectorXd> SamplePoints(int m, double scale) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<Eigen::VectorXd> out{Eigen::VectorXd::Zero(m)};
  for (int s = 0; s < 6; ++s) {
    Eigen::VectorXd d(m);
    for (int i = 0; i < m; ++i) d(i) = u(gen);
    out.push_back(d);
  }
  return out;
}

TEST(RodSetup, JacobianMatchesFiniteDifferencesOfTheRodLengths) {
  const RodGeometry g = ThreeRods();
  const RodSetup setup(g);
  const Eigen::VectorXd l0 = Lengths(g, Eigen::VectorXd::Zero(2));
  for (const auto& d : SamplePoints(2, 0.08)) {
    Eigen::VectorXd a(3);
    setup.CalcCommands(d, a);
    EXPECT_LT((a - (g.p0 + Lengths(g, d) - l0)).cwiseAbs().maxCoeff(), 1e-15);
    const Eigen::MatrixXd j = setup.CalcJacobian(d);
    const double h = 1e-6;
    for (int i = 0; i < 2; ++i) {
      Eigen::VectorXd dp = d, dm = d;
      dp(i) += h;
      dm(i) -= h;
      const Eigen::VectorXd fd = (Lengths(g, dp) - Lengths(g, dm)) / (2.0 * h);
      EXPECT_LT((j.col(i) - fd).cwiseAbs().maxCoeff(), 1e-8) << "slot " << i << " at " << d.transpose();
    }
  }
}

TEST(RodSetup, SlotForcesAreTheGradientOfTheSpecimenPotential) {
  const RodGeometry g = ThreeRods();
  const RodSetup setup(g);
  Eigen::Matrix3d ka;  // actuator coordinates [N/m], symmetric positive definite
  ka << 5000, 1200, -300, 1200, 3000, 400, -300, 400, 4000;
  const Eigen::VectorXd l0 = Lengths(g, Eigen::VectorXd::Zero(2));
  auto potential = [&](const Eigen::VectorXd& d) {
    const Eigen::VectorXd dl = Lengths(g, d) - l0;
    return 0.5 * dl.dot(ka * dl);
  };
  for (const auto& d : SamplePoints(2, 0.08)) {
    Eigen::VectorXd a(3), r(2);
    setup.CalcCommands(d, a);
    const Eigen::VectorXd f = ka * (a - g.p0);  // what the bench would measure
    setup.CalcSlotForces(d, f, r);
    const double h = 1e-6;
    for (int i = 0; i < 2; ++i) {
      Eigen::VectorXd dp = d, dm = d;
      dp(i) += h;
      dm(i) -= h;
      const double grad = (potential(dp) - potential(dm)) / (2.0 * h);
      EXPECT_NEAR(r(i), grad, 1e-6 * std::max(1.0, std::abs(grad))) << "slot " << i;
    }
    // The tangent dr/dd = Jᵀ K_a J + Σ f_k ∂²ℓ_k/∂d² against finite differences of r.
    const Eigen::MatrixXd j = setup.CalcJacobian(d);
    const Eigen::MatrixXd tangent = j.transpose() * ka * j + setup.CalcGeometricStiffness(d, f);
    for (int i = 0; i < 2; ++i) {
      Eigen::VectorXd dp = d, dm = d, ap(3), am(3), rp(2), rm(2);
      dp(i) += h;
      dm(i) -= h;
      setup.CalcCommands(dp, ap);
      setup.CalcCommands(dm, am);
      setup.CalcSlotForces(dp, ka * (ap - g.p0), rp);
      setup.CalcSlotForces(dm, ka * (am - g.p0), rm);
      EXPECT_LT((tangent.col(i) - (rp - rm) / (2.0 * h)).cwiseAbs().maxCoeff(), 1e-4);
    }
  }
  // The geometric stiffness vanishes at zero force and is not zero otherwise.
  const Eigen::Vector2d d(0.05, -0.03);
  EXPECT_EQ(setup.CalcGeometricStiffness(d, Eigen::Vector3d::Zero()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(setup.CalcGeometricStiffness(d, Eigen::Vector3d(100, -50, 80)).cwiseAbs().maxCoeff(), 1.0);
}

TEST(RodSetup, SmallDisplacementsGiveTheLinearSetupOfItsLinearisation) {
  const RodGeometry g = ThreeRods();
  const RodSetup setup(g);
  // T0 = rods' unit axes at d = 0 projected on the slot directions, by hand.
  Eigen::MatrixXd t0(3, 2);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d n = (g.attachments.col(k) - g.bases.col(k)).normalized();
    for (int i = 0; i < 2; ++i) t0(k, i) = n.dot(g.directions.col(i));
  }
  EXPECT_LT((setup.linearisation() - t0).cwiseAbs().maxCoeff(), 1e-15);
  LinearSetup lin_data{g.p0, t0, g.load_cell_zero, {}};
  const LinearActuatorSetup linear(lin_data);
  // The difference of the commands is second order: it falls 4 times when d halves.
  const Eigen::Vector2d dir(0.7, -0.4);
  double last = 0.0;
  for (double eps : {4e-3, 2e-3, 1e-3, 5e-4}) {
    Eigen::VectorXd ag(3), al(3);
    setup.CalcCommands(eps * dir, ag);
    linear.CalcCommands(eps * dir, al);
    const double diff = (ag - al).cwiseAbs().maxCoeff();
    EXPECT_GT(diff, 0.0);
    if (last > 0.0) {
      EXPECT_NEAR(last / diff, 4.0, 0.1) << "at " << eps << " m";
    }
    last = diff;
  }
  // At d = 0 the slot forces are exactly the linear setup's.
  Eigen::VectorXd f(3), rg(2);
  f << 120.0, -40.0, 75.0;
  setup.CalcSlotForces(Eigen::VectorXd::Zero(2), f, rg);
  const Eigen::VectorXd rl = t0.transpose() * f;  // the linear setup's r = Tᵀ f
  EXPECT_LT((rg - rl).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RodSetup, CommandStepBoundHoldsEverywhere) {
  const RodSetup setup(ThreeRods());
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-0.1, 0.1), s(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::Vector2d d(u(gen), u(gen));
    const Eigen::Vector2d step(1e-3 * s(gen), 1e-3 * s(gen));
    Eigen::VectorXd a(3), b(3);
    setup.CalcCommands(d, a);
    setup.CalcCommands(d + step, b);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(b(k) - a(k)), setup.CommandStepBound(k) * step.cwiseAbs().maxCoeff() + 1e-15);
    }
  }
  // Two orthogonal unit directions: the bound is √2, not 2.
  RodGeometry g;
  g.directions = Eigen::Matrix2d::Identity();
  g.bases.resize(2, 2);
  g.bases << -0.4, -0.24, 0.0, -0.32;
  g.attachments = Eigen::Matrix2d::Zero();
  g.p0 = Eigen::Vector2d(0.02, 0.03);
  g.load_cell_zero = Eigen::Vector2d::Zero();
  EXPECT_NEAR(RodSetup(g).CommandStepBound(0), std::sqrt(2.0), 1e-15);
}

RodGeometry TwoRods() {
  RodGeometry g;
  g.directions = Eigen::Matrix2d::Identity();  // flap x, edge y
  g.bases.resize(2, 2);
  g.bases << -0.4, -0.24,
              0.0, -0.32;  // rod 1 along x, rod 2 along (0.6, 0.8), both 0.4 m
  g.attachments = Eigen::Matrix2d::Zero();
  g.p0 = Eigen::Vector2d(0.02, 0.03);
  g.load_cell_zero = Eigen::Vector2d::Zero();
  return g;
}

TEST(RodSetup, SingularityScanFindsRodsThatTurnParallelWithinTheStroke) {
  transfer::SafetyLimits l;
  l.stroke_min = -0.15;
  l.stroke_max = 0.15;
  // Rods of 0.4 m: nothing near singular within ±50 mm.
  EXPECT_FALSE(FindNearSingular(RodSetup(TwoRods()), Eigen::Vector2d(0.05, 0.05), {l, l}, 0.01));
  // Two short rods at right angles: where the specimen reaches the line through both bases
  // (d = (−0.05, −0.05), a corner of the box), they are collinear.
  RodGeometry g = TwoRods();
  g.bases << -0.1, 0.0,
              0.0, -0.1;
  g.p0 = Eigen::Vector2d(0.02, 0.02);
  const RodSetup close(g);
  const auto p = FindNearSingular(close, Eigen::Vector2d(0.05, 0.05), {l, l}, 0.01);
  ASSERT_TRUE(p);
  EXPECT_LT(p->ratio, 0.01);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(close.CalcJacobian(p->d));
  EXPECT_LT(svd.singularValues().minCoeff(),
            0.01 * Eigen::JacobiSVD<Eigen::MatrixXd>(close.linearisation()).singularValues().minCoeff());
  // The same with strokes that keep the specimen away from there: nothing reachable is singular.
  transfer::SafetyLimits tight = l;
  tight.stroke_min = 0.0195;
  tight.stroke_max = 0.0205;
  const auto q = FindNearSingular(close, Eigen::Vector2d(0.05, 0.05), {tight, tight}, 0.01);
  EXPECT_FALSE(q) << q->d.transpose();
}

TEST(RodSetup, BadGeometriesAreConfigErrors) {
  auto error_of = [](const RodGeometry& g) -> std::string {
    try {
      RodSetup s(g);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  RodGeometry g = TwoRods();
  g.bases.col(1) = g.attachments.col(1);  // a rod of zero length
  EXPECT_NE(error_of(g).find("actuators[1]"), std::string::npos) << error_of(g);
  g = TwoRods();
  g.bases.col(1) << -0.8, 0.0;  // both rods along x: J(0) has rank 1
  EXPECT_NE(error_of(g).find("rank 1"), std::string::npos) << error_of(g);
  g = TwoRods();
  g.directions.col(1).setZero();
  EXPECT_NE(error_of(g).find("directions[1]"), std::string::npos) << error_of(g);
  g = TwoRods();
  g.p0 = Eigen::Vector3d::Zero();
  EXPECT_NE(error_of(g).find("p0"), std::string::npos) << error_of(g);
  g = TwoRods();
  g.directions = Eigen::MatrixXd::Identity(4, 2);
  EXPECT_NE(error_of(g).find("2 ([x, y]) or 3"), std::string::npos) << error_of(g);
  g = TwoRods();
  g.attachments(0, 0) = NAN;
  EXPECT_NE(error_of(g).find("finite"), std::string::npos) << error_of(g);
  // A rod through its base at run time is an Error, not a NaN.
  const RodSetup ok(TwoRods());
  Eigen::VectorXd a(2);
  EXPECT_THROW(ok.CalcCommands(Eigen::Vector2d(-0.4, 0.0), a), Error);
}

}  // namespace
}  // namespace hybridtest::substructures
