// RtPlant of several actuators on one coupled specimen: the actuators interact through the
// specimen's off-diagonal stiffness; the servo-hydraulic plant of two actuators on a specimen
// without coupling is two one-actuator plants; with coupling its measured frequency response,
// cross terms included, is the transfer matrix of rt_plant.h; the settled response is the
// static loop; the reader takes per-actuator lists and refuses a list of the wrong length.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/rt_plant.h"

namespace hybridtest::transfer {
namespace {

using cd = std::complex<double>;
constexpr double kPi = std::numbers::pi;

RtPlantConfig TwoServos(double coupling) {
  RtPlantConfig c;
  c.kind = PlantKind::kServoHydraulic;
  c.actuators.assign(2, {});
  c.actuators[1].p0 = 0.03;
  c.actuators[1].servo.gain = 1.0;
  c.specimen.mass = {29.13, 20.0};
  c.specimen.stiffness = {1.19e6, coupling, coupling, 0.8e6};
  c.specimen.damping = {100.0, 0.0, 0.0, 80.0};
  return c;
}

TEST(RtPlantCoupled, IdealActuatorsInteractThroughTheSpecimen) {
  RtPlantConfig c;
  c.actuators.assign(2, {});
  c.actuators[1].p0 = 0.03;
  c.actuators[1].delay = 0.002;
  c.specimen.mass = {0.0, 0.0};
  c.specimen.stiffness = {5000.0, 1200.0, 1200.0, 3000.0};
  c.specimen.damping = {0.0, 0.0, 0.0, 0.0};
  RtPlant plant(c);
  EXPECT_EQ(plant.num_actuators(), 2);
  VirtualClock clock;
  plant.Activate();
  std::vector<Measurement> out(2);
  plant.Execute(std::vector<double>{0.0, 0.03}, out);
  plant.StartPaced(0.001, clock);
  for (int i = 1; i <= 5; ++i) {
    clock.WaitUntil(0.001 * i);
    plant.Execute(std::vector<double>{0.001 * i, 0.03 + 0.002 * i}, out);
    const double x1 = 0.001 * i, x2 = i > 2 ? 0.002 * (i - 2) : 0.0;  // actuator 2: 2 ms late
    EXPECT_DOUBLE_EQ(out[0].position, x1) << i;
    EXPECT_DOUBLE_EQ(out[1].position, 0.03 + x2) << i;
    EXPECT_NEAR(out[0].force, 5000.0 * x1 + 1200.0 * x2, 1e-9) << i;
    EXPECT_NEAR(out[1].force, 1200.0 * x1 + 3000.0 * x2, 1e-9) << i;
  }
  EXPECT_THROW(plant.Execute(std::vector<double>{0.0}, std::span(out).first(1)), TransferError);
}

// x/c at frequency f of actuator i's position to a sine on actuator j's command (the other's
// held at p0), from whole periods after the transient.
cd Measured(const RtPlantConfig& c, int i, int j, double f, double rate) {
  RtPlant plant(c);
  VirtualClock clock;
  plant.Activate();
  std::vector<double> command{c.actuators[0].p0, c.actuators[1].p0};
  std::vector<Measurement> out(2);
  plant.Execute(command, out);
  plant.StartPaced(1.0 / rate, clock);
  const long settle = static_cast<long>(3.0 * rate);
  const long window = static_cast<long>(std::round(4.0 * rate / f));
  cd acc(0.0, 0.0), ref(0.0, 0.0);
  for (long k = 1; k <= settle + window; ++k) {
    clock.WaitUntil(static_cast<double>(k) / rate);
    const double t = clock.Now();
    const double u = 1e-3 * std::sin(2.0 * kPi * f * t);
    command[static_cast<std::size_t>(j)] = c.actuators[static_cast<std::size_t>(j)].p0 + u;
    plant.Execute(command, out);
    if (k > settle) {
      const cd e = std::exp(cd(0.0, -2.0 * kPi * f * t));
      acc += (out[static_cast<std::size_t>(i)].position -
              c.actuators[static_cast<std::size_t>(i)].p0) * e;
      ref += u * e;
    }
  }
  return acc / ref;
}

TEST(RtPlantCoupled, UncoupledServosAreOneActuatorPlantsEach) {
  const RtPlant two(TwoServos(0.0));
  for (int a = 0; a < 2; ++a) {
    RtPlantConfig one;
    one.kind = PlantKind::kServoHydraulic;
    one.actuators = {TwoServos(0.0).actuators[static_cast<std::size_t>(a)]};
    const auto d = static_cast<std::size_t>(3 * a);
    one.specimen = SpecimenLaw::One(TwoServos(0.0).specimen.mass[static_cast<std::size_t>(a)],
                                    TwoServos(0.0).specimen.stiffness[d],
                                    TwoServos(0.0).specimen.damping[d]);
    const RtPlant single(one);
    for (double f : {1.0, 10.0}) {
      const double w = 2.0 * kPi * f;
      EXPECT_NEAR(std::abs(two.FrequencyResponse(w, a, a) - single.FrequencyResponse(w)), 0.0,
                  1e-9) << a << " " << f;
      EXPECT_EQ(two.FrequencyResponse(w, 1 - a, a), cd(0.0)) << a << " " << f;
    }
  }
}

TEST(RtPlantCoupled, CoupledServoResponseIsItsTransferMatrix) {
  const RtPlantConfig c = TwoServos(0.5e6);
  const RtPlant plant(c);
  for (const auto& [i, j] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 1}}) {
    const double f = 5.0, rate = 4096.0;
    const cd measured = Measured(c, i, j, f, rate);
    const cd oracle = plant.FrequencyResponse(2.0 * kPi * f, i, j) *
                      std::exp(cd(0.0, -2.0 * kPi * f * 0.5 / rate));  // half a tick of hold
    EXPECT_NEAR(std::abs(measured - oracle), 0.0, 0.01 * std::abs(oracle) + 1e-6)
        << i << j << " measured " << measured << " oracle " << oracle;
  }
  // The interaction is there: actuator 1's command moves actuator 2.
  EXPECT_GT(std::abs(plant.FrequencyResponse(2.0 * kPi * 5.0, 1, 0)), 0.01);
}

TEST(RtPlantCoupled, SettledResponseIsTheStaticLoop) {
  const RtPlantConfig c = TwoServos(0.5e6);
  RtPlant plant(c);
  plant.Activate();
  std::vector<Measurement> out(2);
  plant.Execute(std::vector<double>{1e-3, 0.03 - 2e-3}, out);
  const double x1 = out[0].position, x2 = out[1].position - 0.03;
  // F = K x, and each servo's loop: x_i = g_i u_i − β2 a3 F_i / a1β0.
  const double f1 = 1.19e6 * x1 + 0.5e6 * x2, f2 = 0.5e6 * x1 + 0.8e6 * x2;
  EXPECT_NEAR(out[0].force, f1, 1e-6);
  EXPECT_NEAR(out[1].force, f2, 1e-6);
  const auto& s = c.actuators[0].servo;
  EXPECT_NEAR(x1, 1.0261 * 1e-3 - s.beta2 * s.a3 * f1 / s.a1_beta0, 1e-14);
  EXPECT_NEAR(x2, 1.0 * -2e-3 - s.beta2 * s.a3 * f2 / s.a1_beta0, 1e-14);
}

TEST(RtPlantCoupled, ASpecimenOfTheWrongSizeIsRefused) {
  RtPlantConfig c = TwoServos(0.0);
  c.specimen.stiffness = {1.0, 2.0};
  EXPECT_THROW(RtPlant{c}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer
