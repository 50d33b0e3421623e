#pragma once
// ExpSetup: how the n trial displacements of an OpenFresco element map to the one actuator of a
// hybridtest bench, and how the actuator's measurement maps back (the OpenFresco "setup" idea
// for a one-actuator truss setup). With T the (1 × n) transform row, d the trial
// displacements, x the actuator's measured offset from p0 and f its measured force:
//
//   actuator command   p = p0 + T d              (T d in wire length units → m)
//   element forces     q = Tᵀ f                  (n × 1)
//   element stiffness  K = Tᵀ K0 T               (n × n, column-major on the wire)
//   element disp.      d_m = Tᵀ (T Tᵀ)⁻¹ x      (the least-norm d with T d_m = x)
//   projected v, a     Tᵀ (T Tᵀ)⁻¹ T v          (the part of v the actuator carries)
//
// q = Tᵀ f is the virtual-work dual of p − p0 = T d (f · δx = q · δd). Numbers on the wire
// are in `wire_units`; everything stored here is SI.
#include <algorithm>
#include <span>
#include <vector>

#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::openfresco {

struct ExpSetup {
  BenchUnits wire_units{1e-3, 1.0, "mm", "N"};  // units of the numbers on the wire
  std::vector<double> transform;   // T, (1 × n) row. Unit: [-] (wire length per wire length).
  double p0 = 0.0;                 // actuator position at T d = 0. Unit: [m].
  double initial_stiffness = 0.0;  // K0, the specimen's initial stiffness. Unit: [N/m].
  // Several actuators (n_act > 1): `transform` holds T row-major (n_act × n), and p0 and K0
  // are per actuator: p0s (n_act) [m], stiffness_matrix K_a (n_act × n_act, row-major) [N/m].
  int actuators = 1;
  std::vector<double> p0s;
  std::vector<double> stiffness_matrix;

  int dofs() const { return static_cast<int>(transform.size()) / std::max(actuators, 1); }
};

// Throws ConfigError unless T is non-empty, finite and not all zero, and K0 is finite and
// non-negative.
void ValidateSetup(const ExpSetup& setup);

// p = p0 + T d, d in wire length units (n values). Unit: [m]. NaN if any d is not finite.
double ActuatorCommand(const ExpSetup& setup, std::span<const double> d);

// q = Tᵀ f, f [N] → n values in wire force units.
std::vector<double> ElementForces(const ExpSetup& setup, double force);

// Tᵀ k T, k [N/m] → n² values in wire force per wire length, column-major.
std::vector<double> ElementStiffness(const ExpSetup& setup, double stiffness);

// d_m = Tᵀ (T Tᵀ)⁻¹ x, x = measured position − p0 [m] → n values in wire length units.
std::vector<double> ElementDisplacement(const ExpSetup& setup, double offset);

// Tᵀ (T Tᵀ)⁻¹ T v, unit-free (v in any wire unit; n values in, n values out).
std::vector<double> ProjectOnActuator(const ExpSetup& setup, std::span<const double> v);

// Several actuators (setup_multi.cc), with T (n_act × n):
// a = p0 + T d [m] per actuator (NaN if any d is not finite).
std::vector<double> ActuatorCommands(const ExpSetup& setup, std::span<const double> d);
// q = Tᵀ f, f (n_act) [N] → n values in wire force units.
std::vector<double> ElementForcesOf(const ExpSetup& setup, std::span<const double> forces);
// Tᵀ K_a T → n² values in wire force per wire length, column-major.
std::vector<double> ElementStiffnessOf(const ExpSetup& setup);
// Tᵀ (T Tᵀ)⁻¹ x, x (n_act) = measured positions − p0 [m] → n values in wire length units.
std::vector<double> ElementDisplacementOf(const ExpSetup& setup, std::span<const double> offsets);
// Tᵀ (T Tᵀ)⁻¹ T v (n values in and out).
std::vector<double> ProjectOnActuators(const ExpSetup& setup, std::span<const double> v);
// Throws ConfigError unless the sizes fit n_act and T has full row rank.
void ValidateMultiSetup(const ExpSetup& setup);

}  // namespace hybridtest::transfer::openfresco
