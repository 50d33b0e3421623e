#pragma once
// ExpSetup: how the n trial displacements of an OpenFresco element map to the n_act ≥ 1
// actuators of a hybridtest bench, and how their measurements map back (the OpenFresco "setup"
// idea for a truss setup of n_act actuators). With T the (n_act × n) transform, d the trial
// displacements (n), x the actuators' measured offsets from p0 (n_act) and f their measured
// forces (n_act):
//
//   actuator commands  a = p0 + T d              (n_act; T d in wire length units → m)
//   element forces     q = Tᵀ f                  (n)
//   element stiffness  K = Tᵀ K_a T              (n × n, column-major on the wire)
//   element disp.      d_m = Tᵀ (T Tᵀ)⁻¹ x      (n; the least-norm d with T d_m = x)
//   projected v, a     Tᵀ (T Tᵀ)⁻¹ T v          (n; the part of v the actuators carry)
//
// q = Tᵀ f is the virtual-work dual of a − p0 = T d (f · δx = q · δd). n_act = 1 (one row t,
// K_a = [K0]) is the ordinary one-actuator setup; its (T Tᵀ)⁻¹ is the division by |t|². Numbers
// on the wire are in `wire_units`; everything stored here is SI.
#include <algorithm>
#include <span>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::openfresco {

struct ExpSetup {
  BenchUnits wire_units{1e-3, 1.0, "mm", "N"};  // units of the numbers on the wire
  int actuators = 1;                   // n_act ≥ 1
  std::vector<double> transform;       // T (n_act × n), row-major. Unit: [-] (wire length per
                                       // wire length).
  std::vector<double> p0s;             // (n_act) actuator positions at T d = 0. Unit: [m].
  std::vector<double> stiffness_matrix;  // K_a (n_act × n_act), row-major: the specimen's
                                         // initial stiffness in actuator coordinates [N/m]

  int dofs() const { return static_cast<int>(transform.size()) / std::max(actuators, 1); }  // n
};

// Throws ConfigError unless the sizes fit n_act (T of n_act rows, one p0 each, an n_act × n_act
// K_a), T is finite with rows of length 1e-6 to 1e6 that are linearly independent, p0 is
// finite, and K_a is finite with a diagonal ≥ 0.
void ValidateSetup(const ExpSetup& setup);

// a = p0 + T d [m], d in wire length units (n) → n_act values; NaN if any d is not finite.
std::vector<double> ActuatorCommands(const ExpSetup& setup, std::span<const double> d);
// q = Tᵀ f, f (n_act) [N] → n values in wire force units.
std::vector<double> ElementForces(const ExpSetup& setup, std::span<const double> forces);
// Tᵀ K_a T → n² values in wire force per wire length, column-major.
std::vector<double> ElementStiffness(const ExpSetup& setup);
// Tᵀ (T Tᵀ)⁻¹ x, x (n_act) = measured positions − p0 [m] → n values in wire length units.
std::vector<double> ElementDisplacement(const ExpSetup& setup, std::span<const double> offsets);
// Tᵀ (T Tᵀ)⁻¹ T v, unit-free (v in any wire unit; n values in, n values out).
std::vector<double> ProjectOnActuators(const ExpSetup& setup, std::span<const double> v);

}  // namespace hybridtest::transfer::openfresco
