// What Build() derives (compile.h): the user's specs stay as written, the compiled frames and
// points carry the derived data; and the solve's factor structure (the pattern the unrolled
// kernels skip, the sparse factorisation of branched trees) against a dense LLT of the same M.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Cholesky>

#include "hybridtest/multibody/kane.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::RandomState;
using test_support::RelativeError;

// A hub spinning about z (q1) with `branches` chains of `links` hinges about each chain's own
// axis, listed parents first: a branched tree with n = 1 + branches · links.
Model BuildStar(int branches, int links) {
  const int n = 1 + branches * links;
  std::vector<QuantityInfo> q;
  for (int k = 0; k < n; ++k) q.push_back({"q" + std::to_string(k + 1), "rad", ""});
  ModelBuilder b(q);
  const FrameId H = b.AddFrameAboutAxis("H", b.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(0));
  b.AddRigidBody("hub", H, b.origin(), 5.0, Eigen::Vector3d(1.0, 1.0, 2.0).asDiagonal());
  int next = 1;
  for (int branch = 0; branch < branches; ++branch) {
    FrameId parent = b.AddFrameAboutAxis("B", H, Eigen::Vector3d::UnitZ(),
                                         ScalarField::Constant(2 * std::numbers::pi * branch / branches));
    PointId tip = b.origin();
    for (int k = 0; k < links; ++k) {
      const FrameId L = b.AddFrameAboutAxis("L", parent, Eigen::Vector3d::UnitY(), ScalarField::Coordinate(next++));
      const PointId G = b.AddPoint("G", tip, L, {ScalarField::Constant(0.2), {}, {}});
      tip = b.AddPoint("P", tip, L, {ScalarField::Constant(0.4), {}, {}});
      b.AddRigidBody("link", L, G, 1.0 + 0.1 * k, Eigen::Vector3d(0.01, 0.02, 0.02).asDiagonal());
      b.AddForce("gravity", G, b.newtonian(), [](const auto& a) {
        using T = std::decay_t<decltype(a.t)>;
        return Vector3<T>(T(0.0), T(0.0), T(-9.81));
      });
      parent = L;
    }
  }
  return std::move(b).Build();
}

// u̇ and its derivatives from the engine against a dense LLT of the engine's own M and g
// (values) and u̇' = M⁻¹ (g' − M' u̇) (AutoDiff directions), at random states.
void ExpectSolveAgrees(const Model& model, double tolerance) {
  const int n = model.num_coordinates();
  std::mt19937 rng(11);
  Data<double> data(model);
  Data<AutoDiff> data_ad(model);
  const Eigen::VectorXd r = Eigen::VectorXd::Zero(model.num_slots());
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd x = RandomState(rng, Eigen::VectorXd::Constant(n, 1.5), 2.0);
    Eigen::VectorXd xdot(2 * n);
    CalcStateDerivative<double>(model, data, 0.2, x, r, xdot);
    const Eigen::VectorXd udot = data.M.llt().solve(data.g);
    EXPECT_LE(RelativeError(xdot.tail(n), udot), tolerance) << "trial " << trial;
    const int seeds = std::min(2 * n, kMaxDerivatives);
    VectorX<AutoDiff> xa(2 * n), xdot_a(2 * n);
    for (int i = 0; i < 2 * n; ++i) {
      xa(i) = AutoDiff(x(i), i < seeds ? Derivatives(Derivatives::Unit(seeds, i))
                                       : Derivatives(Derivatives::Zero(seeds)));
    }
    const VectorX<AutoDiff> ra = r.cast<AutoDiff>();
    CalcStateDerivative<AutoDiff>(model, data_ad, AutoDiff(0.2, Derivatives(Derivatives::Zero(seeds))),
                                  xa, ra, xdot_a);
    for (int d = 0; d < seeds; ++d) {
      Eigen::MatrixXd dM(n, n);
      Eigen::VectorXd dg(n), dudot(n);
      auto part = [d](const AutoDiff& a) { return a.derivatives().size() > d ? a.derivatives()(d) : 0.0; };
      for (int i = 0; i < n; ++i) {
        dg(i) = part(data_ad.g(i));
        dudot(i) = part(xdot_a(n + i));
        for (int j = 0; j < n; ++j) dM(i, j) = part(data_ad.M(i, j));
      }
      const Eigen::VectorXd expected = data.M.llt().solve(dg - dM * udot);
      EXPECT_LE(RelativeError(dudot, expected), 100 * tolerance) << "trial " << trial << ", d/dx_" << d;
    }
  }
}

TEST(CompiledModel, TheSpecsStayAsWritten) {
  ModelBuilder b({{"q1", "rad", ""}, {"q2", "m", ""}});
  const FrameId A = b.AddFrameAboutAxis("A", b.newtonian(), Eigen::Vector3d(0.0, 0.0, 2.0), ScalarField::Coordinate(0));
  const PointId P = b.AddPoint("P", b.origin(), A, {ScalarField::Constant(1.0), ScalarField::Coordinate(1, 0.5), {}});
  b.AddParticle("p", P, 2.0);
  const Model model = std::move(b).Build();
  // The axis as given (not normalised), and nothing derived in the specs.
  EXPECT_EQ(model.frames()[1].axis, Eigen::Vector3d(0.0, 0.0, 2.0));
  EXPECT_TRUE(model.frames()[1].angle.is_affine());
  ASSERT_EQ(model.compiled_frames().size(), model.frames().size());
  ASSERT_EQ(model.compiled_points().size(), model.points().size());
  // The compiled frame and point carry what the engine needs.
  EXPECT_EQ(model.compiled_frames()[1].axis, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(model.compiled_frames()[1].axis_index, 2);
  EXPECT_TRUE(model.compiled_frames()[1].affine_angle);
  EXPECT_EQ(model.compiled_frames()[1].active, std::vector<int>({0}));
  const CompiledPoint& p = model.compiled_points()[1];
  EXPECT_TRUE(p.affine);
  EXPECT_EQ(p.active, std::vector<int>({0, 1}));
  EXPECT_EQ(p.offset, Eigen::Vector3d(1.0, 0.0, 0.0));
  ASSERT_EQ(p.rate_terms.size(), 1u);
  EXPECT_EQ(p.rate_terms[0].speed, 1);
  EXPECT_EQ(p.rate_terms[0].coefficient, 0.5);
  // The same model with a unit axis gives the same equations of motion, bit for bit.
  ModelBuilder u({{"q1", "rad", ""}, {"q2", "m", ""}});
  const FrameId Au = u.AddFrameAboutAxis("A", u.newtonian(), Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(0));
  u.AddParticle("p", u.AddPoint("P", u.origin(), Au, {ScalarField::Constant(1.0), ScalarField::Coordinate(1, 0.5), {}}), 2.0);
  const Model unit = std::move(u).Build();
  const Eigen::Vector4d x(0.3, 0.2, 1.5, -0.7);
  const Eigen::VectorXd r(0);
  EXPECT_EQ(test_support::StateDerivative(model, 0.0, x, r), test_support::StateDerivative(unit, 0.0, x, r));
}

TEST(CompiledModel, TheRotorsFactorHasNoFillIn) {
  // The paper's rotor lists the blades before the hub: an arrow matrix whose factor keeps
  // M's structure (the blades' columns factor independently).
  const auto rotor = test_support::DefaultModel("rotor");
  const std::vector<char>& nz = rotor.model.factor_pattern();
  ASSERT_EQ(nz.size(), 16u);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < i; ++j) EXPECT_EQ(nz[i + 4 * j] != 0, i == 3) << i << ", " << j;
  EXPECT_FALSE(rotor.model.sparse_factor());  // n = 4: the unrolled kernel
  ExpectSolveAgrees(rotor.model, 1e-14);
}

TEST(CompiledModel, BranchedTreesTakeTheSparseFactorisation) {
  for (int links : {4, 6, 12}) {
    SCOPED_TRACE(testing::Message() << "links " << links);
    const Model model = BuildStar(3, links);
    ASSERT_TRUE(model.sparse_factor());
    // Parents first: factored leaves first, with no fill-in (the branches stay uncoupled).
    const SparseFactorPlan& plan = model.sparse_factor_plan();
    EXPECT_TRUE(plan.reversed);
    const int n = model.num_coordinates();
    EXPECT_EQ(static_cast<int>(plan.columns.size()), 3 * links * (links - 1) / 2 + 3 * links);
    ASSERT_EQ(static_cast<int>(plan.row_start.size()), n + 1);
    ExpectSolveAgrees(model, 1e-12);
  }
}

TEST(CompiledModel, ChainsKeepTheDenseFactorisation) {
  for (int n : {5, 12, 30}) {
    std::vector<QuantityInfo> q;
    for (int k = 0; k < n; ++k) q.push_back({"q" + std::to_string(k + 1), "rad", ""});
    ModelBuilder b(q);
    FrameId parent = b.newtonian();
    PointId tip = b.origin();
    for (int k = 0; k < n; ++k) {
      parent = b.AddFrameAboutAxis("L", parent, Eigen::Vector3d::UnitZ(), ScalarField::Coordinate(k));
      tip = b.AddPoint("P", tip, parent, {ScalarField::Constant(0.3), {}, {}});
      b.AddParticle("m", tip, 0.5);
    }
    const Model model = std::move(b).Build();
    EXPECT_FALSE(model.sparse_factor()) << "n = " << n;  // a chain's M is dense
    ExpectSolveAgrees(model, 1e-8);  // a long chain's M is ill-conditioned
  }
}

}  // namespace
}  // namespace hybridtest::multibody
