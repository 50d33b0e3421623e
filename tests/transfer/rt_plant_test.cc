// RtPlant against independent oracles: the servo-hydraulic plant's measured frequency
// response against its transfer function evaluated in complex arithmetic; the static loop; a
// pure delay; the damper law.
#include "hybridtest/transfer/rt_plant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

using cd = std::complex<double>;
constexpr double kPi = std::numbers::pi;

RtPlantConfig Benchmark() {
  RtPlantConfig c;
  c.kind = PlantKind::kServoHydraulic;
  c.specimen = SpecimenLaw::One(29.13, 1.19e6, 2.0 * 0.0097 * std::sqrt(1.19e6 * 29.13));
  return c;
}

// x/c = g·Gs·H / (1 + Gs·H), H = Ga·Gsp / (1 + a2 s Ga Gsp) (rt_plant.h).
cd Oracle(const RtPlantConfig& c, double f) {
  const cd s(0.0, 2.0 * kPi * f);
  const auto& k = c.actuators[0].servo;
  const auto& sp = c.specimen;
  const cd gsp = 1.0 / (sp.mass[0] * s * s + sp.damping[0] * s + sp.stiffness[0]);
  const cd ga = 1.0 / (s + k.a3);
  const cd gs = k.a1_beta0 / (s * s + k.beta1 * s + k.beta2);
  const cd h = ga * gsp / (1.0 + k.a2 * s * ga * gsp);
  return k.gain * gs * h / (1.0 + gs * h);
}

// Drives the plant with a sine of frequency f at `rate` Hz and returns the measured response
// x/c at f, from the last `periods` whole periods (after the transient).
cd Measured(RtPlant& plant, double f, double rate, double amplitude = 1e-3) {
  VirtualClock clock;
  plant.Activate();
  ExecuteOne(plant, 0.0);
  plant.StartPaced(1.0 / rate, clock);
  const long settle = static_cast<long>(3.0 * rate), window = static_cast<long>(std::round(4.0 * rate / f));
  cd acc(0.0, 0.0), ref(0.0, 0.0);
  for (long i = 1; i <= settle + window; ++i) {
    clock.WaitUntil(static_cast<double>(i) / rate);
    const double t = clock.Now();
    const double c = amplitude * std::sin(2.0 * kPi * f * t);
    const Measurement m = ExecuteOne(plant, c);
    if (i > settle) {
      const cd e = std::exp(cd(0.0, -2.0 * kPi * f * t));
      acc += m.position * e;
      ref += c * e;
    }
  }
  return acc / ref;
}

TEST(RtPlant, ServoHydraulicFrequencyResponseMatchesItsTransferFunction) {
  for (double f : {1.0, 5.0, 10.0, 20.0}) {
    RtPlant plant(Benchmark());
    const cd measured = Measured(plant, f, 4096.0);
    // The plant samples the command at the tick and holds it: half a tick of extra lag.
    const cd oracle = Oracle(Benchmark(), f) * std::exp(cd(0.0, -2.0 * kPi * f * 0.5 / 4096.0));
    EXPECT_NEAR(std::abs(measured), std::abs(oracle), 0.01 * std::abs(oracle)) << f << " Hz";
    EXPECT_NEAR(std::arg(measured), std::arg(oracle), 0.01) << f << " Hz";
  }
  // The benchmark's delay: about 25 ms at 1 Hz.
  const double delay_1hz = -std::arg(Oracle(Benchmark(), 1.0)) / (2.0 * kPi);
  EXPECT_NEAR(delay_1hz, 0.025, 0.001);
}

TEST(RtPlant, SettledResponseIsTheStaticLoop) {
  RtPlant plant(Benchmark());
  plant.Activate();
  const Measurement m = ExecuteOne(plant, 1e-3);
  EXPECT_NEAR(m.position / 1e-3, std::abs(Oracle(Benchmark(), 1e-9)), 1e-9);
  EXPECT_NEAR(m.force, 1.19e6 * m.position, 1e-6);
}

TEST(RtPlant, PureDelayReturnsTheCommandOfTauAgo) {
  RtPlantConfig c;
  c.one().delay = 0.003;
  c.specimen.stiffness = {1000.0};
  RtPlant plant(c);
  VirtualClock clock;
  plant.Activate();
  ExecuteOne(plant, 0.0);
  plant.StartPaced(0.001, clock);
  for (int i = 1; i <= 10; ++i) {
    clock.WaitUntil(0.001 * i);
    const Measurement m = ExecuteOne(plant, static_cast<double>(i));
    EXPECT_DOUBLE_EQ(m.position, i > 3 ? static_cast<double>(i - 3) : 0.0) << i;
    EXPECT_DOUBLE_EQ(m.force, 1000.0 * m.position);
  }
}

TEST(RtPlant, DamperLawIsRateDependent) {
  const SpecimenLaw law = SpecimenLaw::One(0.0, 0.0, 200.0, 0.5);
  EXPECT_DOUBLE_EQ(law.Force(0.0, 0.04, 0.0), 200.0 * 0.2);
  EXPECT_DOUBLE_EQ(law.Force(0.0, -0.04, 0.0), -200.0 * 0.2);
}

TEST(RtPlant, BadConfigIsRefusedNamingTheField) {
  RtPlantConfig c;
  c.kind = PlantKind::kServoHydraulic;  // no specimen mass
  try {
    RtPlant plant(c);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("specimen.mass"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hybridtest::transfer
