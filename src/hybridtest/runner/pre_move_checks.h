#pragma once
// Checks made before anything moves, so that a slip (a step beyond the scheme's stability
// limit, a setup.p0 that disagrees with the bench) is refused with a ConfigError (exit 2 on the
// command line) instead of producing diverged results or a jump of the actuator. Every Session
// makes them when it is built (session.h, SessionOptions::pre_move_checks), so the command line,
// campaigns, `plan`, Python and any program embedding the library are refused alike; `probe`
// calls CheckPhysicalSlotsBeforeMoving itself.
#include <memory>
#include <vector>

#include "hybridtest/io/run_spec.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

// The per-slot stiffness the stability check uses (num_slots entries), in slot order: a
// numerical slot's law's initial stiffness, a physical slot's `safety.initial_stiffness` if
// given, else the model's nominal slot stiffness. Unit: [N/m] (or [N·m/rad]).
std::vector<double> SlotStiffnessForStability(const io::RunSpec& spec);

// The linearised stability of the explicit tableau `spec.scheme.tableau` at step `dt` [s] at
// the initial state. The state Jacobian J = ∂f/∂x (multibody::CalcStateJacobian) is completed
// with the substructures' stiffness: with r_i ≈ k_i d_i(q),
//
//   J_total = J + (∂f/∂r) K (∂d/∂q),  ∂f/∂r (2n × m) exact (f is affine in r),
//   ∂d/∂q (m × n) by central differences, K = diag(k_i) (SlotStiffnessForStability)
//
// Throws ConfigError naming spec.scheme.dt_where and the largest stable step
// (integrators/stability.h) when dt is beyond it. Returns that step [s] (+infinity if nothing
// limits it).
double CheckStepStability(const io::RunSpec& spec, double dt);

// The check above for the configured scheme: explicit Runge–Kutta at dt; MR-OS's RK4 substeps
// at `integrator.substep`; α-OS treats the numerical model implicitly (no limit). Returns the
// largest stable step [s] (+infinity if nothing limits it).
double CheckSchemeStability(const io::RunSpec& spec);

// Each physical slot's setup against what its transfer system announces
// (TransferSystem::Announce; an emulated bench announces its p0 and limits, a remote bench its
// limits only after connecting, where the client checks them itself, a Python driver its `p0`
// if it has one):
//   - p0: |setup.p0 − the bench's p0| must not exceed kP0Tolerance × safety.max_increment;
//     else the first command would jump, or the specimen start loaded. The ConfigError names
//     substructures.<slot>.setup.p0, both values (the bench's also in mm) and, for a ratio
//     near 1000, the unit slip;
//   - limits: transfer::CheckLimitsAgainstBench, both directions.
// `subs` are the spec's substructures, built (one per spec.substructures entry). Throws
// ConfigError. Sends nothing to any bench.
inline constexpr double kP0Tolerance = 0.1;
void CheckPhysicalSlotsBeforeMoving(
    const io::RunSpec& spec, const std::vector<std::unique_ptr<substructures::Substructure>>& subs);

// Both checks, in that order (what a Session makes when it is built).
void CheckBeforeMoving(const io::RunSpec& spec,
                       const std::vector<std::unique_ptr<substructures::Substructure>>& subs);

}  // namespace hybridtest::runner
