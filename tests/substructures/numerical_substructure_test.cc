// NumericalSubstructure: a law in the loop. Trials never change the committed state; only
// Commit does (checked with the path-dependent Bouc–Wen law, where it matters).
#include "hybridtest/substructures/numerical_substructure.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/linear_spring.h"
#include "substructures/trial_one.h"

namespace hybridtest::substructures {
namespace {

using testing::TrialOne;

// k0 = 7200 N/m, 10 % post-yield, yield at 2 mm.
std::unique_ptr<constitutive::RestoringForceLaw> MakeBoucWen() {
  return std::make_unique<constitutive::BoucWen>(
      constitutive::BoucWen::FromYieldDisplacement(7200.0, 0.1, 0.002));
}

TEST(NumericalSubstructure, LinearSpringIsKTimesD) {
  NumericalSubstructure sub(std::make_unique<constitutive::LinearSpring>(7200.0));
  EXPECT_DOUBLE_EQ(TrialOne(sub, 0.003, {}), 21.6);
  EXPECT_FALSE(sub.is_physical());
  EXPECT_EQ(sub.evaluations(), 0);
  EXPECT_NE(sub.Describe().find("numerical"), std::string::npos);
}

TEST(NumericalSubstructure, RejectsNoLaw) {
  EXPECT_THROW(NumericalSubstructure(nullptr), Error);
}

TEST(NumericalSubstructure, BoucWenTrialsDoNotCommit) {
  NumericalSubstructure sub(MakeBoucWen());
  const double first = TrialOne(sub, 0.01, {0, 0, 0.0});
  // Any number of other trials (stages of the same step) leave the committed state alone.
  for (double d : {0.02, -0.01, 0.005, 0.0}) TrialOne(sub, d, {0, 1, 0.0});
  EXPECT_EQ(TrialOne(sub, 0.01, {0, 0, 0.0}), first);
  // Back at zero without a commit: the virgin state, no force.
  EXPECT_EQ(TrialOne(sub, 0.0, {0, 0, 0.0}), 0.0);
}

TEST(NumericalSubstructure, BoucWenCommitMakesTheLastTrialPermanent) {
  NumericalSubstructure committed(MakeBoucWen());
  NumericalSubstructure fresh(MakeBoucWen());
  // Beyond yield and committed there: unloading to zero leaves a residual force.
  TrialOne(committed, 0.01, {0, 0, 0.0});
  committed.Commit();
  const double residual = TrialOne(committed, 0.0, {1, 0, 0.001});
  EXPECT_GT(std::abs(residual), 1.0) << "the commit at 10 mm left no hysteresis";
  EXPECT_EQ(TrialOne(fresh, 0.0, {1, 0, 0.001}), 0.0);
  // Only the last trial before Commit counts: trial far away, then back, then commit.
  NumericalSubstructure last(MakeBoucWen());
  TrialOne(last, 0.05, {0, 0, 0.0});
  TrialOne(last, 0.01, {0, 1, 0.0});
  last.Commit();
  EXPECT_EQ(TrialOne(last, 0.0, {1, 0, 0.001}), residual);
}

}  // namespace
}  // namespace hybridtest::substructures
