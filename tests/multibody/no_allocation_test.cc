// CalcStateDerivative<double> does no heap allocation after the first call (it runs inside
// every integrator stage of a real-time hybrid test), for each built-in model. Counted with
// tests/support/alloc_counter.h; skipped where malloc cannot be counted.
#include <gtest/gtest.h>

#include <random>

#include "hybridtest/multibody/kane.h"
#include "support/alloc_counter.h"
#include "support/multibody_helpers.h"

namespace hybridtest::multibody {
namespace {

using test_support::CountAllocations;

class NoAllocationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!test_support::kCanCountAllocations) {
      GTEST_SKIP() << "malloc cannot be counted in this build (sanitizer or non-glibc)";
    }
  }
};

TEST_F(NoAllocationTest, StateDerivativeDoesNotAllocate) {
  std::mt19937 rng(41);
  for (const std::string& name : models::ModelNames()) {
    const models::BuiltModel built = test_support::DefaultModel(name);
    const Model& model = built.model;
    Data<double> data(model);
    const Eigen::VectorXd x = test_support::RandomState(rng, test_support::CoordinateScales(built), 2.0);
    const Eigen::VectorXd r = test_support::RandomForces(rng, model.num_slots(), 100.0);
    Eigen::VectorXd xdot(model.num_states()), d(model.num_slots());
    CalcStateDerivative<double>(model, data, 0.0, x, r, xdot);  // first call
    const long allocations = CountAllocations([&] {
      for (int i = 0; i < 10; ++i) {
        CalcStateDerivative<double>(model, data, 0.01 * i, x, r, xdot);
        CalcSlotDisplacements<double>(model, data, 0.01 * i, x.head(model.num_coordinates()), d);
      }
    });
    EXPECT_EQ(allocations, 0) << name;
    EXPECT_TRUE(xdot.allFinite()) << name;
  }
}

// Positive control: building a workspace allocates, and the counter sees it.
TEST_F(NoAllocationTest, CounterSeesTheWorkspaceAllocations) {
  const models::BuiltModel built = test_support::DefaultModel("rotor");
  EXPECT_GT(CountAllocations([&] { Data<double> data(built.model); }), 0);
}

}  // namespace
}  // namespace hybridtest::multibody
