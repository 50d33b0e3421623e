// SlotLaw / EmulatedSlotLaw: the emulated specimen's law as the slot sees it equals, trial for
// trial, what the physical substructure measures on an ideal emulated bench (no lag, no noise)
// through a setup that is not the identity (a lever, flipped signs, a preload, a load-cell
// offset), with a hysteretic specimen.
#include "hybridtest/substructures/slot_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hybridtest/constitutive/bouc_wen.h"
#include "hybridtest/substructures/numerical_substructure.h"
#include "hybridtest/substructures/physical_substructure.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "substructures/trial_one.h"

namespace hybridtest::substructures {
namespace {

using testing::TrialOne;

transfer::EmulatedBenchConfig IdealBoucWenBench() {
  transfer::EmulatedBenchConfig c = transfer::DefaultEmulatedBenchConfig();
  c.specimen = std::make_shared<constitutive::BoucWen>(
      constitutive::BoucWen::FromYieldDisplacement(5250.0, 0.3, 0.004, 2.0));
  c.p0 = 0.020;  // [m]
  c.initial_position = 0.020;
  c.offset = 3.0;  // [N]
  c.lag.type = transfer::ServoLag::Type::kNone;
  c.delay = 0.0;
  c.velocity_limit = 10.0;  // [m/s]: every move in one internal step
  c.noise_std = 0.0;
  c.resolution = 0.0;
  c.settle_dwell = 0.0;
  c.sampling_window = 0.001;
  c.overhead = 0.0;
  return c;
}

TEST(SlotLaw, EqualsWhatThePhysicalSubstructureMeasuresThroughANonIdentitySetup) {
  SetupTransform setup;
  setup.p0 = 0.021;            // 1 mm off the bench's zero-force position: a preload
  setup.sign = -1.0;
  setup.scale = 0.5;           // a lever
  setup.force_sign = -1.0;
  setup.force_scale = 2.0;
  setup.load_cell_zero = 1.0;  // [N], not the bench's 3 N offset
  transfer::SafetyLimits limits;
  limits.max_increment = 0.02;
  PhysicalSubstructure physical(
      "r1", std::make_unique<transfer::EmulatedBench>(IdealBoucWenBench()), setup, limits);
  std::unique_ptr<constitutive::RestoringForceLaw> law = EmulatedSlotLaw(physical);
  ASSERT_NE(law, nullptr);
  EXPECT_DOUBLE_EQ(law->initial_stiffness(), -1.0 * 2.0 * -1.0 * 0.5 * 5250.0);
  physical.Activate();
  // Out past yield and back, twice (Bouc–Wen: the path matters).
  for (int k = 0; k <= 60; ++k) {
    const double d = 0.03 * std::sin(0.21 * k) * (1.0 + 0.01 * k);  // [m] slot displacement
    const double measured = TrialOne(physical, d, {k, 0, 0.0});
    const double modelled = law->Trial(d);
    law->Commit();
    EXPECT_NEAR(modelled, measured, 1e-9 * std::max(1.0, std::abs(measured))) << "trial " << k;
  }
}

TEST(SlotLaw, IsNullForANumericalSubstructure) {
  NumericalSubstructure numerical(std::make_unique<constitutive::BoucWen>(
      constitutive::BoucWen::FromYieldDisplacement(5250.0, 0.3, 0.004, 2.0)));
  EXPECT_EQ(EmulatedSlotLaw(numerical), nullptr);
}

}  // namespace
}  // namespace hybridtest::substructures
