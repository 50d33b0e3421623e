#pragma once
// SetupTransform: how a model displacement becomes an actuator command and a measured force
// becomes a restoring force — the geometry and units of the test setup. This is where units
// change: the model side is SI, the bench side speaks the bench's units (BenchUnits).
//
//   command [m]         = p0 + sign · scale · d                 (the paper: q1 + p0)
//   command [bench]     = command [m] / metres_per_length_unit
//   force [N]           = measured [bench] · newtons_per_force_unit − load_cell_zero
//   r^s [N]             = force_sign · force_scale · force [N]
//
// The substructure computes with it as the linear setup of one actuator (OneActuatorSetup,
// actuator_setup.h: T = [sign · scale], R = [force_sign · force_scale]).
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::substructures {

struct SetupTransform {
  double p0 = 0.0;              // actuator position where the specimen carries no force [m]
  double sign = 1.0;            // +1 or −1: actuator axis relative to the model displacement
  double scale = 1.0;           // actuator displacement per model displacement [-]
  double force_sign = 1.0;      // +1 or −1: load-cell axis relative to r^s
  double force_scale = 1.0;     // r^s per measured force [-]
  double load_cell_zero = 0.0;  // reading at zero load, subtracted [N]

  // Throws ConfigError if sign/force_sign are not ±1 or a scale is not positive and finite.
  void Validate() const;
  double CommandMetres(double displacement) const { return p0 + sign * scale * displacement; }
  double ToBench(double metres, const transfer::BenchUnits& u) const {
    return metres / u.metres_per_length_unit;
  }
  double PositionMetres(double bench_position, const transfer::BenchUnits& u) const {
    return bench_position * u.metres_per_length_unit;
  }
  double ForceNewtons(double bench_force, const transfer::BenchUnits& u) const {
    return bench_force * u.newtons_per_force_unit - load_cell_zero;
  }
};

}  // namespace hybridtest::substructures
