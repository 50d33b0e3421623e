// The composite mass matrix of a tree of joints (tree_mass.h, decision 0012) against the
// pairwise sum (CalcMassMatrixPairwise), at random states, for doubles and for AutoDiff (the
// coupling matrix and Jacobian paths); and which models take which path.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Cholesky>

#include "hybridtest/multibody/kane.h"
#include "hybridtest/multibody/tree_mass.h"
#include "support/alloc_counter.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::RandomState;
using test_support::RelativeError;

// A planar (or, with `twist`, spatial) chain of n revolute links with a particle at each tip
// and, with `bodies`, a rigid body per link.
Model BuildChain(int n, bool twist, bool bodies) {
  std::vector<QuantityInfo> q;
  for (int k = 0; k < n; ++k) q.push_back({"q" + std::to_string(k + 1), "rad", ""});
  ModelBuilder b(q);
  FrameId parent = b.newtonian();
  PointId tip = b.origin();
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d axis = twist ? Eigen::Vector3d::Unit(k % 3) : Eigen::Vector3d::UnitZ();
    const FrameId L = b.AddFrameAboutAxis("L", parent, axis, ScalarField::Coordinate(k));
    const PointId G = b.AddPoint("G", tip, L, {ScalarField::Constant(0.15), ScalarField::Constant(0.01 * k), {}});
    tip = b.AddPoint("P", tip, L, {ScalarField::Constant(0.3), {}, {}});
    b.AddParticle("m", tip, 0.5 + 0.1 * k);
    if (bodies) {
      Eigen::Matrix3d I;
      I << 0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.04;
      b.AddRigidBody("link", L, G, 1.0 + 0.05 * k, I);
    }
    parent = L;
  }
  return std::move(b).Build();
}

// A tower that sways (prismatic q1), a nacelle that yaws (q2) and a hub that spins (q3) about
// an axis off the yaw axis; three blades of `links` revolute links each (flap about the
// blade's y), with bodies and tip masses, and a prismatic tip slider on blade 1: a branched
// tree with both joint kinds and pivots away from O.
Model BuildTurbine(int links) {
  const int n = 3 + 3 * links + 1;
  std::vector<QuantityInfo> q;
  for (int k = 0; k < n; ++k) q.push_back({"q" + std::to_string(k + 1), "", ""});
  ModelBuilder b(q);
  const Eigen::Matrix3d I = Eigen::Vector3d(0.3, 0.5, 0.7).asDiagonal();
  const PointId top = b.AddPoint("top", b.origin(), b.newtonian(),
                                 {ScalarField::Coordinate(0), {}, ScalarField::Constant(20.0)});
  b.AddParticle("tower top", top, 50.0);
  const FrameId Y = b.AddFrameAboutAxis("Y", b.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(1));
  // Wrong on purpose would be placing the nacelle from O; it hangs from the tower top.
  const PointId hub = b.AddPoint("hub", top, Y, {ScalarField::Constant(-1.5), {}, ScalarField::Constant(0.5)});
  b.AddRigidBody("nacelle", Y, top, 30.0, I);
  const FrameId H = b.AddFrameAboutAxis("H", Y, Eigen::Vector3d::UnitX(), ScalarField::Coordinate(2));
  b.AddRigidBody("hub", H, hub, 10.0, I);
  int next = 3;
  for (int blade = 0; blade < 3; ++blade) {
    FrameId parent = b.AddFrameAboutAxis("B", H, Eigen::Vector3d::UnitX(),
                                         ScalarField::Constant(2 * std::numbers::pi * blade / 3));
    PointId tip = hub;
    for (int k = 0; k < links; ++k) {
      const FrameId L = b.AddFrameAboutAxis("L", parent, Eigen::Vector3d::UnitY(), ScalarField::Coordinate(next++));
      const PointId G = b.AddPoint("G", tip, L, {ScalarField(), ScalarField(), ScalarField::Constant(0.4)});
      tip = b.AddPoint("P", tip, L, {ScalarField(), ScalarField(), ScalarField::Constant(0.8)});
      b.AddRigidBody("segment", L, G, 2.0, 0.1 * I);
      parent = L;
    }
    if (blade == 0) {
      tip = b.AddPoint("slider", tip, parent, {ScalarField::Coordinate(next++, 0.5), {}, {}});
    }
    b.AddParticle("tip", tip, 1.0);
  }
  return std::move(b).Build();
}

// M by both paths at 20 random states, for doubles and AutoDiff (derivatives w.r.t. x).
void ExpectPathsAgree(const Model& model, double tolerance) {
  const int n = model.num_coordinates();
  std::mt19937 rng(7);
  Data<double> tree(model), pairwise(model);
  Data<AutoDiff> tree_ad(model), pairwise_ad(model);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 2.0), 3.0);
    CalcKinematics<double>(model, tree, 0.3, x);
    CalcKinematics<double>(model, pairwise, 0.3, x);
    if (model.is_joint_tree()) {
      internal::CalcTreeMassMatrix<double>(model, tree);
    } else {
      CalcMassMatrix<double>(model, tree);
    }
    CalcMassMatrixPairwise<double>(model, pairwise);
    EXPECT_LE(RelativeError(tree.M, pairwise.M), tolerance) << "trial " << trial;
    EXPECT_TRUE(tree.M.isApprox(tree.M.transpose(), 0.0));
    // AutoDiff: seed a few directions of x.
    VectorX<AutoDiff> xa(2 * n);
    const int seeds = std::min(2 * n, kMaxDerivatives);
    for (int i = 0; i < 2 * n; ++i) {
      xa(i) = AutoDiff(x(i), i < seeds ? Derivatives(Derivatives::Unit(seeds, i))
                                       : Derivatives(Derivatives::Zero(seeds)));
    }
    CalcKinematics<AutoDiff>(model, tree_ad, AutoDiff(0.3, Derivatives(Derivatives::Zero(seeds))), xa);
    CalcKinematics<AutoDiff>(model, pairwise_ad, AutoDiff(0.3, Derivatives(Derivatives::Zero(seeds))), xa);
    if (model.is_joint_tree()) {
      internal::CalcTreeMassMatrix<AutoDiff>(model, tree_ad);
    } else {
      CalcMassMatrix<AutoDiff>(model, tree_ad);
    }
    CalcMassMatrixPairwise<AutoDiff>(model, pairwise_ad);
    for (int d = 0; d < seeds; ++d) {
      Eigen::MatrixXd a(n, n), p(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // A zero entry that no term touched has no derivative vector.
          const auto& da = tree_ad.M(i, j).derivatives();
          const auto& dp = pairwise_ad.M(i, j).derivatives();
          a(i, j) = da.size() > d ? da(d) : 0.0;
          p(i, j) = dp.size() > d ? dp(d) : 0.0;
        }
      EXPECT_LE(RelativeError(a, p), tolerance) << "trial " << trial << ", ∂M/∂x_" << d;
    }
  }
}

TEST(TreeMassMatrix, ChainsTakeTheTreePathAndAgree) {
  for (int n : {1, 2, 5, 12, 40}) {
    for (bool twist : {false, true}) {
      for (bool bodies : {false, true}) {
        SCOPED_TRACE(testing::Message() << "n = " << n << ", twist " << twist << ", bodies " << bodies);
        const Model model = BuildChain(n, twist, bodies);
        ASSERT_TRUE(model.is_joint_tree()) << model.tree_mass_matrix_reason();
        // Large chains take the tree path; n = 1 or 2 may keep the cheaper pairwise sum.
        if (n >= 12) {
          EXPECT_TRUE(model.tree_mass_matrix()) << model.tree_mass_matrix_reason();
        }
        // Composite inertias about O carry m |p|² terms: rounding grows with the chain's
        // reach (12 m at n = 40), still far inside the oracle's 1e-10.
        ExpectPathsAgree(model, 1e-11);
      }
    }
  }
}

TEST(TreeMassMatrix, ABranchedTreeWithPrismaticJointsAgrees) {
  for (int links : {1, 4}) {
    const Model model = BuildTurbine(links);
    ASSERT_TRUE(model.is_joint_tree()) << model.tree_mass_matrix_reason();
    if (links == 4) {
      EXPECT_TRUE(model.tree_mass_matrix()) << model.tree_mass_matrix_reason();
    }
    ExpectPathsAgree(model, 1e-12);
  }
}

TEST(TreeMassMatrix, BuiltInModelsTakeTheRightPath) {
  // The rotor and the double pendulum are joint trees, small enough that the pairwise sum is
  // cheaper (and their results stay bit-identical to earlier builds); the tree plan agrees.
  const auto rotor = test_support::DefaultModel("rotor");
  EXPECT_TRUE(rotor.model.is_joint_tree()) << rotor.model.tree_mass_matrix_reason();
  EXPECT_FALSE(rotor.model.tree_mass_matrix());
  ExpectPathsAgree(rotor.model, 1e-13);
  const auto pendulum = test_support::DefaultModel("double_pendulum");
  EXPECT_TRUE(pendulum.model.is_joint_tree()) << pendulum.model.tree_mass_matrix_reason();
  ExpectPathsAgree(pendulum.model, 1e-13);
  // The spinning top has q̇ = W(q) u: the pairwise path.
  const auto top = test_support::DefaultModel("spinning_top");
  EXPECT_FALSE(top.model.is_joint_tree());
  EXPECT_FALSE(top.model.tree_mass_matrix());
  EXPECT_NE(top.model.tree_mass_matrix_reason().find("W(q)"), std::string::npos);
}

TEST(TreeMassMatrix, ModelsThatAreNotTreesOfJointsTakeThePairwisePath) {
  // One coordinate turning two frames (coupled joints).
  {
    ModelBuilder b({{"q1", "rad", ""}});
    const FrameId A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(0));
    const FrameId B = b.AddFrameAboutAxis("B", A, Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(0, 2.0));
    b.AddParticle("p", b.AddPoint("P", b.origin(), B, {ScalarField::Constant(1.0), {}, {}}), 1.0);
    const Model model = std::move(b).Build();
    EXPECT_FALSE(model.is_joint_tree());
    EXPECT_NE(model.tree_mass_matrix_reason().find("exactly one"), std::string::npos);
    ExpectPathsAgree(model, 0.0);
  }
  // A point carried by a turning point but placed in a frame that does not turn.
  {
    ModelBuilder b({{"q1", "rad", ""}});
    const FrameId A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(0));
    const PointId P = b.AddPoint("P", b.origin(), A, {ScalarField::Constant(1.0), {}, {}});
    const PointId Q = b.AddPoint("Q", P, b.newtonian(), {ScalarField::Constant(1.0), {}, {}});
    b.AddParticle("q", Q, 1.0);
    const Model model = std::move(b).Build();
    EXPECT_FALSE(model.is_joint_tree());
    EXPECT_NE(model.tree_mass_matrix_reason().find("does not turn"), std::string::npos);
  }
  // Two entries into a turning frame from different points (no single pivot).
  {
    ModelBuilder b({{"q1", "m", ""}, {"q2", "rad", ""}});
    const PointId S = b.AddPoint("S", b.origin(), b.newtonian(), {ScalarField::Coordinate(0), {}, {}});
    const FrameId A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(1));
    b.AddParticle("p", b.AddPoint("P", b.origin(), A, {ScalarField::Constant(1.0), {}, {}}), 1.0);
    b.AddParticle("r", b.AddPoint("R", S, A, {ScalarField::Constant(1.0), {}, {}}), 1.0);
    const Model model = std::move(b).Build();
    EXPECT_FALSE(model.is_joint_tree());
    ExpectPathsAgree(model, 0.0);
  }
}

// The tree path and the blocked factorisation of large models allocate nothing per call.
TEST(TreeMassMatrix, LargeModelsDoNotAllocate) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "malloc cannot be counted here";
  for (const Model& model : {BuildChain(40, true, true), BuildTurbine(8)}) {
    ASSERT_TRUE(model.tree_mass_matrix());
    const int n = model.num_coordinates();
    Data<double> data(model);
    std::mt19937 rng(3);
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 1.0), 1.0);
    const Eigen::VectorXd r(0);
    Eigen::VectorXd xdot(2 * n);
    CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);
    EXPECT_EQ(test_support::CountAllocations([&] {
      for (int i = 0; i < 5; ++i) CalcStateDerivative<double>(model, data, 0.01 * i, x, r, xdot);
    }), 0);
    // The solve agrees with a plain LLT of the pairwise M.
    Data<double> check(model);
    CalcKinematics<double>(model, check, 0.04, x);
    CalcMassMatrixPairwise<double>(model, check);
    CalcForcing<double>(model, check, r);
    const Eigen::VectorXd udot = check.M.llt().solve(check.g);
    EXPECT_LT(RelativeError(xdot.tail(n), udot), 1e-9);
  }
}

}  // namespace
}  // namespace hybridtest::multibody
