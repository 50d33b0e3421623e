// SetupTransform: units at the hardware seam (m/N, mm/N and mm/kN benches), sign, scale, p0
// and the load-cell zero, forwards and back.
#include "hybridtest/substructures/setup_transform.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hybridtest/common/error.h"

namespace hybridtest::substructures {
namespace {

const transfer::BenchUnits kSi{};
const transfer::BenchUnits kMmN{1e-3, 1.0, "mm", "N"};
const transfer::BenchUnits kMmKn{1e-3, 1e3, "mm", "kN"};

TEST(SetupTransform, DefaultIsIdentityOnAnSiBench) {
  const SetupTransform s;
  EXPECT_EQ(s.CommandMetres(0.0123), 0.0123);
  EXPECT_EQ(s.ToBench(0.0123, kSi), 0.0123);
  EXPECT_EQ(s.PositionMetres(0.0123, kSi), 0.0123);
  EXPECT_EQ(s.ForceNewtons(88.5, kSi), 88.5);
  EXPECT_EQ(s.RestoringForce(88.5), 88.5);
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
  EXPECT_DOUBLE_EQ(s.RestoringForce(100.0), -50.0);
  EXPECT_DOUBLE_EQ(s.RestoringForce(-100.0), 50.0);
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
          const double r = s.RestoringForce(s.ForceNewtons(bench_force, units));
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

}  // namespace
}  // namespace hybridtest::substructures
