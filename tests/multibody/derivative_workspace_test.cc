// The allocation-free state Jacobian and coupling matrix (derivatives.h): equal to central
// finite differences of the right-hand side, agree with the allocating forms, work for 100
// coordinates and 32 slots (several chunks of kMaxDerivatives directions), and allocate nothing
// after the workspace is built.
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/modelfile/model_file.h"
#include "hybridtest/multibody/derivatives.h"
#include "support/alloc_counter.h"
#include "support/chain_model_file.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

models::BuiltModel Chain(int n, int slots) {
  const modelfile::ModelFile file = modelfile::ParseModelFile(
      YamlInput::FromText(test_support::ChainModelFile(n, slots), "chain.yaml"));
  return modelfile::BuildModelFile(file, file.parameters);
}

double MaxRelative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// J against central differences of f_rhs, B against differences of g in r (exact up to
// round-off: g is affine in r), and the allocating forms against the workspace forms.
void CheckDerivatives(int n, int slots, double fd_tolerance) {
  const models::BuiltModel built = Chain(n, slots);
  const Model& model = built.model;
  ASSERT_EQ(model.num_coordinates(), n);
  ASSERT_EQ(model.num_slots(), slots);
  std::mt19937 rng(5);
  const Eigen::VectorXd x = test_support::RandomState(rng, Eigen::VectorXd::Constant(n, 0.3), 0.5);
  const Eigen::VectorXd r = test_support::RandomForces(rng, slots, 2.0);
  DerivativeWorkspace ws(model);
  Eigen::MatrixXd J(2 * n, 2 * n), B(n, slots);
  CalcStateJacobian(model, ws, 0.2, x, r, J);
  CalcCouplingMatrix(model, ws, 0.2, x, B);
  // q̇ = u: the upper blocks are exactly [0 I].
  EXPECT_EQ(J.topLeftCorner(n, n).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((J.topRightCorner(n, n) - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 0.0);
  const double h = 1e-6;
  for (int col = 0; col < 2 * n; col += 7) {
    Eigen::VectorXd xp = x, xm = x;
    xp(col) += h;
    xm(col) -= h;
    const Eigen::VectorXd fd = (test_support::StateDerivative(model, 0.2, xp, r) -
                                test_support::StateDerivative(model, 0.2, xm, r)) / (2 * h);
    EXPECT_LT(MaxRelative(J.col(col), fd), fd_tolerance) << "column " << col;
  }
  Data<double> data(model);
  Eigen::VectorXd xdot(2 * n);
  for (int s = 0; s < slots; ++s) {
    Eigen::VectorXd rp = r, rm = r;
    rp(s) += 1.0;
    rm(s) -= 1.0;
    CalcStateDerivative<double>(model, data, 0.2, x, rp, xdot);
    const Eigen::VectorXd gp = data.g;
    CalcStateDerivative<double>(model, data, 0.2, x, rm, xdot);
    EXPECT_LT(MaxRelative(B.col(s), (gp - data.g) / 2.0), 1e-12) << "slot " << s;
  }
  EXPECT_EQ(MaxRelative(CalcStateJacobian(model, 0.2, x, r), J), 0.0);
  EXPECT_EQ(MaxRelative(CalcCouplingMatrix(model, 0.2, x), B), 0.0);
}

// Two chunks of kMaxDerivatives directions for J (24 states); one for B.
TEST(DerivativeWorkspaceTest, TwelveCoordinatesMatchFiniteDifferences) { CheckDerivatives(12, 12, 1e-4); }

// 13 chunks for J, 2 for B. A 100-link chain is badly conditioned (M's condition number is
// large), so central differences themselves are only good to about 1e-2 here.
TEST(DerivativeWorkspaceTest, HundredCoordinatesAndThirtyTwoSlots) { CheckDerivatives(100, 32, 5e-2); }

TEST(DerivativeWorkspaceTest, NoAllocationAfterTheWorkspaceIsBuilt) {
  if (!test_support::kCanCountAllocations) GTEST_SKIP() << "malloc cannot be counted here";
  std::mt19937 rng(9);
  for (const models::BuiltModel& built :
       {test_support::DefaultModel("rotor"), test_support::DefaultModel("spinning_top"),
        Chain(40, 20)}) {
    const Model& model = built.model;
    const int n = model.num_coordinates();
    const Eigen::VectorXd x =
        test_support::RandomState(rng, Eigen::VectorXd::Constant(n, 0.3), 0.5);
    const Eigen::VectorXd r = test_support::RandomForces(rng, model.num_slots(), 2.0);
    DerivativeWorkspace ws(model);
    Eigen::MatrixXd J(2 * n, 2 * n), B(n, model.num_slots());
    CalcStateJacobian(model, ws, 0.0, x, r, J);  // first call
    const long allocations = test_support::CountAllocations([&] {
      for (int i = 0; i < 3; ++i) {
        CalcStateJacobian(model, ws, 0.1 * i, x, r, J);
        CalcCouplingMatrix(model, ws, 0.1 * i, x, B);
      }
    });
    EXPECT_EQ(allocations, 0) << built.name;
    EXPECT_TRUE(J.allFinite() && B.allFinite()) << built.name;
  }
}

TEST(DerivativeWorkspaceTest, WrongOutputSizeIsRefused) {
  const models::BuiltModel built = test_support::DefaultModel("rotor");
  DerivativeWorkspace ws(built.model);
  Eigen::MatrixXd J(7, 8);
  EXPECT_THROW(CalcStateJacobian(built.model, ws, 0.0, Eigen::VectorXd::Zero(8),
                                 Eigen::VectorXd::Zero(3), J), ModelError);
}

}  // namespace
}  // namespace hybridtest::multibody
