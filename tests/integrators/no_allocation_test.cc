// ExplicitRungeKutta::Step does no heap allocation (a real-time requirement: the step runs
// between actuator commands). Allocations are counted with tests/support/alloc_counter.h
// (malloc replaced by a counting forwarder); under AddressSanitizer the test is skipped.
#include <gtest/gtest.h>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"
#include "support/alloc_counter.h"

namespace hybridtest::integrators {
namespace {

using hybridtest::test_support::CountAllocations;

class NoAllocationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!hybridtest::test_support::kCanCountAllocations) {
      GTEST_SKIP() << "malloc cannot be counted in this build (sanitizer or non-glibc)";
    }
  }
};

TEST_F(NoAllocationTest, CounterSeesEigenAndOperatorNew) {
  // Positive control: without it, the test below could pass by counting nothing.
  EXPECT_GE(CountAllocations([] {
              Eigen::VectorXd v(64);
              v.setZero();
              EXPECT_EQ(v.sum(), 0.0);
            }),
            1);
  EXPECT_GE(CountAllocations([] {
              // volatile: the compiler may otherwise elide a new/delete pair.
              static double* volatile sink = nullptr;
              sink = new double(1.0);
              delete sink;
            }),
            1);
}

TEST_F(NoAllocationTest, StepDoesNotAllocate) {
  constexpr int kN = 8;
  for (const ButcherTableau& tableau : Catalogue()) {
    ExplicitRungeKutta stepper(tableau, kN);
    const Eigen::MatrixXd J = -Eigen::MatrixXd::Identity(kN, kN);
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(kN, 0.0, 1.0);
    Eigen::VectorXd x_next(kN);
    auto stage = [&](int, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
      for (int r = 0; r < kN; ++r) k(r) = J.row(r).dot(x_i) + t_i;
    };
    const long allocations = CountAllocations([&] {
      for (int n = 0; n < 10; ++n) {
        stepper.Step(n * 0.01, 0.01, x, stage, x_next);
        stepper.Step(n * 0.01, 0.01, x_next, stage, x_next);  // in place
      }
    });
    EXPECT_EQ(allocations, 0) << tableau.name;
    EXPECT_TRUE(x_next.allFinite());
  }
}

TEST_F(NoAllocationTest, StepAllocatesOnlyToResizeAWronglySizedOutput) {
  // Positive control through Step itself: the documented one allocation is seen.
  ExplicitRungeKutta stepper(FindTableau("rk4"), 4);
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(4);
  Eigen::VectorXd x_next;
  auto stage = [](int, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    for (Eigen::Index r = 0; r < x_i.size(); ++r) k(r) = -x_i(r);
  };
  EXPECT_EQ(CountAllocations([&] { stepper.Step(0.0, 0.1, x, stage, x_next); }), 1);
  EXPECT_EQ(CountAllocations([&] { stepper.Step(0.0, 0.1, x, stage, x_next); }), 0);
}

}  // namespace
}  // namespace hybridtest::integrators
