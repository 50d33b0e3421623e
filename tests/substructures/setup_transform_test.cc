// SetupTransform: units at the hardware seam (m/N, mm/N and mm/kN benches), sign, scale, p0
// and the load-cell zero, forwards and back; and the one linear setup of n = 1 it makes
// (OneActuatorSetup), whose arithmetic is the scalar one, bit for bit.
#include "hybridtest/substructures/setup_transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"
#include "hybridtest/substructures/actuator_setup.h"

namespace hybridtest::substructures {
namespace {

const transfer::BenchUnits kSi{};
const transfer::BenchUnits kMmN{1e-3, 1.0, "mm", "N"};
const transfer::BenchUnits kMmKn{1e-3, 1e3, "mm", "kN"};

// The slot force r = force_sign · force_scale · f (the one-actuator setup's R).
double RestoringForce(const SetupTransform& s, double force_newtons) {
  const LinearActuatorSetup setup(OneActuatorSetup(s));
  Eigen::VectorXd d = Eigen::VectorXd::Zero(1), f = Eigen::VectorXd::Constant(1, force_newtons);
  Eigen::VectorXd r(1);
  setup.CalcSlotForces(d, f, r);
  return r(0);
}

TEST(SetupTransform, DefaultIsIdentityOnAnSiBench) {
  const SetupTransform s;
  EXPECT_EQ(s.CommandMetres(0.0123), 0.0123);
  EXPECT_EQ(s.ToBench(0.0123, kSi), 0.0123);
  EXPECT_EQ(s.PositionMetres(0.0123, kSi), 0.0123);
  EXPECT_EQ(s.ForceNewtons(88.5, kSi), 88.5);
  EXPECT_EQ(RestoringForce(s, 88.5), 88.5);
}

TEST(SetupTransform, CommandIsP0PlusSignedScaledDisplacement) {
  SetupTransform s;
  s.p0 = 0.020;
  EXPECT_DOUBLE_EQ(s.CommandMetres(0.005), 0.025);
  EXPECT_DOUBLE_EQ(s.CommandMetres(-0.005), 0.015);
  EXPECT_EQ(s.CommandMetres(0.0), 0.020);  // zero displacement is exactly p0
  s.sign = -1.0;
  EXPECT_DOUBLE_EQ(s.CommandMetres(0.005), 0.015);
  s.scale = 2.0;
  EXPECT_DOUBLE_EQ(s.CommandMetres(0.005), 0.010);
}

TEST(SetupTransform, MillimetreBenchGetsMillimetres) {
  SetupTransform s;
  s.p0 = 0.020;
  // 20 mm + 5 mm.
  EXPECT_NEAR(s.ToBench(s.CommandMetres(0.005), kMmN), 25.0, 1e-12);
  EXPECT_NEAR(s.PositionMetres(25.0, kMmN), 0.025, 1e-15);
}

TEST(SetupTransform, KilonewtonBenchForcesBecomeNewtons) {
  SetupTransform s;
  EXPECT_DOUBLE_EQ(s.ForceNewtons(1.5, kMmKn), 1500.0);
  EXPECT_DOUBLE_EQ(s.ForceNewtons(-0.036, kMmKn), -36.0);
  EXPECT_DOUBLE_EQ(s.ForceNewtons(1.5, kMmN), 1.5);
}

TEST(SetupTransform, LoadCellZeroIsSubtractedInNewtons) {
  SetupTransform s;
  s.load_cell_zero = 12.0;  // [N], also on a kN bench
  EXPECT_DOUBLE_EQ(s.ForceNewtons(0.012, kMmKn), 0.0);
  EXPECT_DOUBLE_EQ(s.ForceNewtons(1.012, kMmKn), 1000.0);
  EXPECT_DOUBLE_EQ(s.ForceNewtons(12.0, kMmN), 0.0);
}

TEST(SetupTransform, RestoringForceAppliesForceSignAndScale) {
  SetupTransform s;
  s.force_sign = -1.0;
  s.force_scale = 0.5;
  EXPECT_DOUBLE_EQ(RestoringForce(s, 100.0), -50.0);
  EXPECT_DOUBLE_EQ(RestoringForce(s, -100.0), 50.0);
}

// A linear specimen k on a kN/mm bench behind any sign/scale/p0/zero combination gives
// r^s = force_sign · force_scale · k · sign · scale · d: the chain is consistent.
TEST(SetupTransform, RoundTripThroughALinearSpecimen) {
  const double k = 7200.0;  // [N/m]
  for (double sign : {1.0, -1.0}) {
    for (double scale : {1.0, 2.5}) {
      for (const auto& units : {kSi, kMmN, kMmKn}) {
        SetupTransform s;
        s.p0 = 0.020;
        s.sign = sign;
        s.scale = scale;
        s.force_sign = sign;  // the load cell turns with the actuator
        s.load_cell_zero = 3.0;
        s.Validate();
        for (double d : {-0.01, 0.0, 0.0042}) {
          const double bench_command = s.ToBench(s.CommandMetres(d), units);
          // The specimen, in SI, then expressed in bench units with the load-cell zero added.
          const double position = s.PositionMetres(bench_command, units);
          const double bench_force = (k * (position - s.p0) + s.load_cell_zero) /
                                     units.newtons_per_force_unit;
          const double r = RestoringForce(s, s.ForceNewtons(bench_force, units));
          EXPECT_NEAR(position, s.CommandMetres(d), 1e-15);
          EXPECT_NEAR(r, k * scale * d, 1e-9) << "sign " << sign << " scale " << scale
                                             << " units " << units.length_name << "/"
                                             << units.force_name << " d " << d;
        }
      }
    }
  }
}

TEST(SetupTransform, ValidateRejectsBadSignsScalesAndNonFiniteOffsets) {
  auto rejects = [](SetupTransform s) { EXPECT_THROW(s.Validate(), ConfigError); };
  SetupTransform good;
  good.p0 = 0.02;
  EXPECT_NO_THROW(good.Validate());
  SetupTransform s = good;
  s.sign = 0.5;
  rejects(s);
  s = good;
  s.force_sign = 0.0;
  rejects(s);
  s = good;
  s.scale = 0.0;
  rejects(s);
  s = good;
  s.force_scale = -1.0;
  rejects(s);
  s = good;
  s.scale = std::numeric_limits<double>::infinity();
  rejects(s);
  s = good;
  s.p0 = std::numeric_limits<double>::quiet_NaN();
  rejects(s);
  s = good;
  s.load_cell_zero = std::numeric_limits<double>::infinity();
  rejects(s);
}

// The one-actuator setup is the linear setup's case n = m = 1 (issue 46: one setup type):
// commands, slot forces, K0 and its inverse are those of SetupTransform's arithmetic, equal
// to the last bit, for scales that round (0.37, 2.9) and flipped signs; the force factor is
// its own (force_sign · force_scale, not T).
TEST(OneActuatorSetup, IsTheLinearSetupOfOneActuatorWithTheScalarArithmetic) {
  for (double sign : {1.0, -1.0}) {
    for (double force_sign : {1.0, -1.0}) {
      SetupTransform s;
      s.p0 = 0.0213;
      s.sign = sign;
      s.scale = 0.37;
      s.force_sign = force_sign;
      s.force_scale = 2.9;
      s.load_cell_zero = 1.7;
      const LinearActuatorSetup setup(OneActuatorSetup(s));
      EXPECT_EQ(setup.num_actuators(), 1);
      EXPECT_EQ(setup.num_slots(), 1);
      EXPECT_EQ(setup.kind(), "linear");
      EXPECT_EQ(setup.load_cell_zero()(0), 1.7);
      EXPECT_EQ(setup.CommandStepBound(0), 0.37);
      EXPECT_FALSE(setup.is_identity());
      Eigen::VectorXd d(1), a(1), f(1), r(1);
      for (double x : {-0.0123, 0.0, 0.004567, 1.0 / 3.0}) {
        d(0) = x;
        setup.CalcCommands(d, a);
        EXPECT_EQ(a(0), s.CommandMetres(x)) << x;
        f(0) = 1234.5678 * x + 0.1;
        setup.CalcSlotForces(d, f, r);
        EXPECT_EQ(r(0), s.force_sign * s.force_scale * f(0)) << x;
      }
      const double k = 7219.3;  // [N/m]
      EXPECT_EQ(setup.SlotStiffness(Eigen::MatrixXd::Constant(1, 1, k))(0, 0),
                k * s.sign * s.scale * s.force_sign * s.force_scale);
      EXPECT_EQ(setup.ActuatorStiffness(Eigen::MatrixXd::Constant(1, 1, k))(0, 0),
                k / (s.sign * s.scale * s.force_sign * s.force_scale));
    }
  }
  EXPECT_TRUE(LinearActuatorSetup(OneActuatorSetup(SetupTransform{})).is_identity());
  SetupTransform bad;
  bad.sign = 0.5;
  EXPECT_THROW(OneActuatorSetup(bad), ConfigError);
}

}  // namespace
}  // namespace hybridtest::substructures
