#include "hybridtest/transfer/numerical_loopback.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/constitutive/linear_spring.h"

namespace hybridtest::transfer {
namespace {

TEST(NumericalLoopback, ReturnsTheLawExactlyInSI) {
  NumericalLoopback loopback(std::make_unique<constitutive::LinearSpring>(7200.0), 0.02);
  EXPECT_EQ(loopback.bench_units().length_name, "m");
  EXPECT_EQ(loopback.bench_units().force_name, "N");
  loopback.Activate();
  const Measurement m = ExecuteOne(loopback, 0.0234);
  EXPECT_EQ(m.position, 0.0234);
  EXPECT_EQ(m.force, 7200.0 * (0.0234 - 0.02));
  EXPECT_EQ(m.lab_time, 0.0);
}

TEST(NumericalLoopback, CommitsEveryCommandLikeAPhysicalSpecimen) {
  const auto params = constitutive::BoucWen::FromYieldDisplacement(5000.0, 0.1, 0.002);
  NumericalLoopback loopback(std::make_unique<constitutive::BoucWen>(params), 0.0);
  constitutive::BoucWen reference(params);
  loopback.Activate();
  for (double x : {0.001, 0.004, 0.002, -0.001}) {
    const double expected = reference.Trial(x);
    reference.Commit();
    EXPECT_EQ(ExecuteOne(loopback, x).force, expected);
  }
}

TEST(NumericalLoopback, LifecycleAndNullLaw) {
  NumericalLoopback loopback(std::make_unique<constitutive::LinearSpring>(1.0), 0.0);
  EXPECT_THROW(ExecuteOne(loopback, 0.0), TransferError);
  loopback.Activate();
  loopback.Hold();
  EXPECT_THROW(ExecuteOne(loopback, 0.0), TransferError);
  EXPECT_THROW(NumericalLoopback(nullptr, 0.0), ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
