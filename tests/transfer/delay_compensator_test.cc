// DelayCompensator around an rt_plant with a pure delay: the polynomial extrapolation is exact
// for a polynomial target of its order; ATS identifies the delay and the amplitude.
#include "hybridtest/transfer/delay_compensator.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/rt_plant.h"
#include "runner/plant_pair.h"

namespace hybridtest::transfer {
namespace {

std::unique_ptr<RtPlant> DelayedPlant(double delay, PlantKind kind = PlantKind::kIdeal) {
  RtPlantConfig c;
  c.kind = kind;
  c.one().delay = delay;
  c.one().lag = 0.004;
  c.specimen.stiffness = {1000.0};
  return std::make_unique<RtPlant>(c);
}

TEST(DelayCompensator, PolynomialIsExactForAQuadraticTarget) {
  CompensatorConfig k;
  k.method = CompensationMethod::kPolynomial;
  k.delay = 0.010;
  k.order = 2;
  DelayCompensator comp(DelayedPlant(0.010), k);
  VirtualClock clock;
  comp.Activate();
  ExecuteOne(comp, 0.0);
  comp.StartPaced(0.001, clock);
  double worst = 0.0;
  for (int i = 1; i <= 200; ++i) {
    clock.WaitUntil(0.001 * i);
    const double t = clock.Now();
    const Measurement m = ExecuteOne(comp, 3.0 * t * t - t);
    if (i > 40) worst = std::max(worst, std::abs(m.position - (3.0 * t * t - t)));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(DelayCompensator, WithoutCompensationTheDelayedPlantLags) {
  // The oracle of the test above: the same target through the plant alone is off.
  auto plant = DelayedPlant(0.010);
  VirtualClock clock;
  plant->Activate();
  ExecuteOne(*plant, 0.0);
  plant->StartPaced(0.001, clock);
  double worst = 0.0;
  for (int i = 1; i <= 200; ++i) {
    clock.WaitUntil(0.001 * i);
    const double t = clock.Now();
    worst = std::max(worst, std::abs(ExecuteOne(*plant, 3.0 * t * t - t).position - (3.0 * t * t - t)));
  }
  EXPECT_GT(worst, 1e-3);
}

TEST(DelayCompensator, AtsIdentifiesTheDelayOfALaggingPlant) {
  CompensatorConfig k;  // ATS, the lab's settings; initial a1 = 20 ms
  k.delay = 0.020;
  k.threshold = 1e-4;
  DelayCompensator comp(DelayedPlant(0.012, PlantKind::kElectromechanical), k);
  VirtualClock clock;
  comp.Activate();
  ExecuteOne(comp, 0.0);
  const double h = 1.0 / 1024.0;
  comp.StartPaced(h, clock);
  double sq = 0.0, ref = 0.0;
  for (int i = 1; i <= 20 * 1024; ++i) {
    clock.WaitUntil(h * i);
    const double t = clock.Now();
    const double x = 0.005 * std::sin(2.0 * std::numbers::pi * 1.5 * t);
    const Measurement m = ExecuteOne(comp, x);
    if (i > 15 * 1024) {
      sq += (m.position - x) * (m.position - x);
      ref += x * x;
    }
  }
  // Delay 12 ms + lag 4 ms (≈ 3.9 ms of phase at 1.5 Hz) + half a tick of hold ≈ 16.4 ms.
  EXPECT_NEAR(comp.actuator(0).estimated_delay(), 0.0164, 0.0015);
  EXPECT_GT(comp.actuator(0).updates(), 100);
  EXPECT_LT(std::sqrt(sq / ref), 0.02);  // tracking within 2 % RMS
}

TEST(DelayCompensator, EachOfTwoActuatorsIsCompensatedForItsOwnDelay) {
  CompensatorConfig k;  // ATS from 15 ms for both
  k.delay = 0.015;
  k.threshold = 1e-4;
  DelayCompensator comp(std::make_unique<runner::test::PlantPair>(
                            std::vector{1000.0, 2000.0}, std::vector{0.0, 0.01}, nullptr,
                            std::vector{0.008, 0.025}),
                        k);
  ASSERT_EQ(comp.num_actuators(), 2);
  VirtualClock clock;
  comp.Activate();
  std::vector<Measurement> m(2);
  const std::vector<double> settled{0.0, 0.01};
  comp.Execute(settled, m);
  const double h = 1.0 / 1024.0;
  comp.StartPaced(h, clock);
  std::array<double, 2> sq{}, ref{};
  for (int i = 1; i <= 12 * 1024; ++i) {
    clock.WaitUntil(h * i);
    const double t = clock.Now();
    const std::vector<double> x{0.004 * std::sin(2.0 * std::numbers::pi * 1.5 * t),
                                0.01 + 0.003 * std::sin(2.0 * std::numbers::pi * 2.0 * t)};
    comp.Execute(x, m);
    for (std::size_t a = 0; a < 2 && i > 8 * 1024; ++a) {
      sq[a] += (m[a].position - x[a]) * (m[a].position - x[a]);
      ref[a] += (x[a] - settled[a]) * (x[a] - settled[a]);
    }
  }
  // Each estimate is its own actuator's delay, from the same start.
  EXPECT_NEAR(comp.actuator(0).estimated_delay(), 0.008, 0.0015);
  EXPECT_NEAR(comp.actuator(1).estimated_delay(), 0.025, 0.0015);
  EXPECT_EQ(comp.compensated_delay(), comp.actuator(0).estimated_delay());  // the smaller
  for (std::size_t a = 0; a < 2; ++a) EXPECT_LT(std::sqrt(sq[a] / ref[a]), 0.02) << a;
  const nlohmann::json record = comp.CompensationRecord();
  ASSERT_EQ(record["actuators"].size(), 2u) << record.dump();
  EXPECT_EQ(record["actuators"][1]["estimated_delay_s"], comp.actuator(1).estimated_delay());
}

TEST(DelayCompensator, RefusesBoundsThatCannotHold) {
  CompensatorConfig k;
  k.lower[1] = 0.1;
  k.upper[1] = 0.0;
  EXPECT_THROW(DelayCompensator(DelayedPlant(0.0), k), ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
