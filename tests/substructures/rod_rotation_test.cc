// RodSetup with a rotational slot: a planar platform on three actuators (x, y, θ, as in
// OpenFresco's three-actuator setup) and a 3-D specimen turning about a tilted axis. The
// oracle moves the attachment points with Eigen::AngleAxisd (not the setup's own Rodrigues
// formula) and differentiates the rod lengths numerically: J, r = J(d)ᵀ f against the
// potential's gradient, the tangent with the geometric stiffness, the step bound and T0.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/rod_setup.h"

namespace hybridtest::substructures {
namespace {

// Three rods on a planar platform: slots x [m], y [m], θ [rad] about o = (0.1, 0.05).
RodGeometry Platform() {
  RodGeometry g;
  g.directions.resize(2, 3);
  g.directions << 1.0, 0.0, 0.0,
                  0.0, 1.0, 0.0;
  g.rotation_slot = 2;
  g.rotation_point = Eigen::Vector2d(0.1, 0.05);
  g.bases.resize(2, 3);
  g.attachments.resize(2, 3);
  g.bases << -0.6, -0.1, 0.5,
              0.1, -0.7, -0.65;
  g.attachments << 0.0, -0.1, 0.3,
                   0.1, 0.0, 0.0;
  g.p0 = Eigen::Vector3d(0.02, 0.03, 0.01);
  g.load_cell_zero = Eigen::Vector3d::Zero();
  return g;
}

// A 3-D specimen: translations along x and (0, 0.6, 0.8), a turn about a tilted axis.
RodGeometry Tilted() {
  RodGeometry g;
  g.directions.resize(3, 3);
  g.directions << 1.0, 0.0, 0.0,
                  0.0, 0.6, 0.0,
                  0.0, 0.8, 0.0;
  g.rotation_slot = 2;
  g.rotation_point = Eigen::Vector3d(0.05, -0.02, 0.1);
  g.rotation_axis = Eigen::Vector3d(0.3, 0.2, 1.0);  // normalised by the setup
  g.bases.resize(3, 4);
  g.attachments.resize(3, 4);
  g.bases << -0.6, 0.1, 0.5, 0.05,
              0.1, -0.7, 0.2, 0.1,
              0.0, 0.1, -0.3, 0.7;
  g.attachments << 0.0, 0.05, 0.2, 0.02,
                   0.1, 0.0, 0.0, 0.1,
                   0.0, 0.02, 0.0, 0.2;
  g.p0 = Eigen::Vector4d(0.02, 0.03, 0.01, 0.0);
  g.load_cell_zero = Eigen::Vector4d::Zero();
  return g;
}

// The oracle's rod lengths: each attachment point translated, then turned about the axis.
Eigen::VectorXd Lengths(const RodGeometry& g, const Eigen::VectorXd& d) {
  const int dim = static_cast<int>(g.directions.rows());
  Eigen::VectorXd l(g.bases.cols());
  for (Eigen::Index k = 0; k < l.size(); ++k) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), o = Eigen::Vector3d::Zero(), axis(0, 0, 1);
    c.head(dim) = g.attachments.col(k);
    o.head(dim) = g.rotation_point;
    if (dim == 3) axis = Eigen::Vector3d(g.rotation_axis(0), g.rotation_axis(1), g.rotation_axis(2)).normalized();
    Eigen::Vector3d p = o + Eigen::AngleAxisd(d(g.rotation_slot), axis) * (c - o);
    for (Eigen::Index i = 0; i < d.size(); ++i) {
      if (i != g.rotation_slot) p.head(dim) += d(i) * g.directions.col(i);
    }
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    b.head(dim) = g.bases.col(k);
    l(k) = (p - b).norm();
  }
  return l;
}

void CheckAgainstTheOracle(const RodGeometry& g, const Eigen::MatrixXd& ka) {
  const RodSetup setup(g);
  const int m = setup.num_slots(), n = setup.num_actuators();
  const Eigen::VectorXd l0 = Lengths(g, Eigen::VectorXd::Zero(m));
  auto potential = [&](const Eigen::VectorXd& d) {
    const Eigen::VectorXd dl = Lengths(g, d) - l0;
    return 0.5 * dl.dot(ka * dl);
  };
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-0.06, 0.06), th(-0.4, 0.4);
  for (int sample = 0; sample < 8; ++sample) {
    Eigen::VectorXd d(m);
    for (int i = 0; i < m; ++i) d(i) = i == g.rotation_slot ? th(gen) : u(gen);
    if (sample == 0) d.setZero();
    Eigen::VectorXd a(n), r(m);
    setup.CalcCommands(d, a);
    EXPECT_LT((a - (g.p0 + Lengths(g, d) - l0)).cwiseAbs().maxCoeff(), 1e-14);
    const Eigen::MatrixXd j = setup.CalcJacobian(d);
    const Eigen::VectorXd f = ka * (a - g.p0);
    setup.CalcSlotForces(d, f, r);
    const Eigen::MatrixXd tangent = j.transpose() * ka * j + setup.CalcGeometricStiffness(d, f);
    const double h = 1e-6;
    for (int i = 0; i < m; ++i) {
      Eigen::VectorXd dp = d, dm = d;
      dp(i) += h;
      dm(i) -= h;
      const Eigen::VectorXd fd = (Lengths(g, dp) - Lengths(g, dm)) / (2.0 * h);
      EXPECT_LT((j.col(i) - fd).cwiseAbs().maxCoeff(), 1e-8) << "J, slot " << i;
      const double grad = (potential(dp) - potential(dm)) / (2.0 * h);
      EXPECT_NEAR(r(i), grad, 1e-6 * std::max(1.0, std::abs(grad))) << "r, slot " << i;
      Eigen::VectorXd ap(n), am(n), rp(m), rm(m);
      setup.CalcCommands(dp, ap);
      setup.CalcCommands(dm, am);
      setup.CalcSlotForces(dp, ka * (ap - g.p0), rp);
      setup.CalcSlotForces(dm, ka * (am - g.p0), rm);
      EXPECT_LT((tangent.col(i) - (rp - rm) / (2.0 * h)).cwiseAbs().maxCoeff(),
                1e-5 * std::max(1.0, tangent.cwiseAbs().maxCoeff()))
          << "tangent, slot " << i;
    }
    // The step bound: |Δa_k| ≤ B_k max_i |Δd_i| for a step in every slot at once.
    Eigen::VectorXd step(m), b(n);
    for (int i = 0; i < m; ++i) step(i) = (i % 2 ? -1e-3 : 1e-3);
    setup.CalcCommands(d + step, b);
    for (int k = 0; k < n; ++k) {
      EXPECT_LE(std::abs(b(k) - a(k)), setup.CommandStepBound(k) * 1e-3 + 1e-15) << "rod " << k;
    }
  }
}

TEST(RodRotation, PlanarPlatformOnThreeActuatorsMatchesTheOracle) {
  Eigen::Matrix3d ka;
  ka << 6000, 800, -400, 800, 4000, 300, -400, 300, 5000;
  CheckAgainstTheOracle(Platform(), ka);
  // T0's rotation column: n_k · (ẑ × (c_k − o)), by hand for rod 1 (along x, arm (−0.1, 0.05)).
  const RodSetup setup(Platform());
  const Eigen::Vector2d n1 = Eigen::Vector2d(0.6, 0.0).normalized();
  EXPECT_NEAR(setup.linearisation()(0, 2), n1.dot(Eigen::Vector2d(-0.05, -0.1)), 1e-15);
  EXPECT_NEAR(setup.lever_arm(0), std::hypot(0.1, 0.05), 1e-15);
}

TEST(RodRotation, TiltedAxisIn3dMatchesTheOracle) {
  Eigen::Matrix4d ka;
  ka << 6000, 800, -400, 100, 800, 4000, 300, 0, -400, 300, 5000, 200, 100, 0, 200, 3000;
  CheckAgainstTheOracle(Tilted(), ka);
}

TEST(RodRotation, BadRotationsAreConfigErrors) {
  RodGeometry g = Tilted();
  g.rotation_axis = Eigen::Vector3d::Zero();
  EXPECT_THROW(RodSetup{g}, ConfigError);
  g = Tilted();
  g.rotation_point = Eigen::Vector2d::Zero();
  EXPECT_THROW(RodSetup{g}, ConfigError);
  g = Platform();
  g.rotation_point = Platform().attachments.col(0);  // ...
  g.attachments.col(1) = g.rotation_point;            // two rods whose arms cannot
  g.attachments.col(2) = g.rotation_point;            // turn: J(0) loses rank
  EXPECT_THROW(RodSetup{g}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::substructures
