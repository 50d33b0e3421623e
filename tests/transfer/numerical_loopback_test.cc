#include "hybridtest/transfer/numerical_loopback.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

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

TEST(NumericalLoopback, EachOfSeveralActuatorsHasItsOwnLawAndP0) {
  std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> laws;
  laws.push_back(std::make_unique<constitutive::LinearSpring>(7200.0));
  laws.push_back(std::make_unique<constitutive::LinearSpring>(3000.0));
  NumericalLoopback loopback(std::move(laws), {0.02, -0.01});
  ASSERT_EQ(loopback.num_actuators(), 2);
  loopback.Activate();
  const std::vector<double> commands{0.025, 0.0};
  std::vector<Measurement> out(2);
  loopback.Execute(commands, out);
  EXPECT_EQ(out[0].position, 0.025);
  EXPECT_EQ(out[0].force, 7200.0 * (0.025 - 0.02));
  EXPECT_EQ(out[1].position, 0.0);
  EXPECT_EQ(out[1].force, 3000.0 * (0.0 + 0.01));
  // One command for two actuators is refused, naming the count.
  std::vector<Measurement> one(1);
  try {
    loopback.Execute(std::span<const double>(commands.data(), 1), one);
    FAIL() << "expected a TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("2 actuator"), std::string::npos) << e.what();
  }
  std::vector<std::unique_ptr<constitutive::RestoringForceLaw>> short_p0;
  short_p0.push_back(std::make_unique<constitutive::LinearSpring>(1.0));
  short_p0.push_back(std::make_unique<constitutive::LinearSpring>(1.0));
  EXPECT_THROW(NumericalLoopback(std::move(short_p0), {0.0}), ConfigError);
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
