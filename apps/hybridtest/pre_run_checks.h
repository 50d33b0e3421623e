#pragma once
// Checks made before a run starts, so that a slip (a step beyond the scheme's stability limit,
// a run that would fill the disk) is refused with exit 2 instead of producing diverged results
// or failing hours later.
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::app {

// The linearised stability of the explicit scheme at the initial state. The state Jacobian
// J = ∂f/∂x (multibody::CalcStateJacobian) is completed with the substructures' stiffness:
// with r_i ≈ k_i d_i(q),
//
//   J_total = J + (∂f/∂r) K (∂d/∂q),  ∂f/∂r (2n × m) exact (f is affine in r),
//   ∂d/∂q (m × n) by central differences, K = diag(k_i)
//
// where k_i is a numerical slot's law's initial stiffness, a physical slot's
// `safety.initial_stiffness` if given, else the model's nominal slot stiffness. Throws
// ConfigError naming integrator.dt and the largest stable step (integrators/stability.h) when
// dt is beyond it. Returns that step [s] (+infinity if nothing limits it).
double CheckStepStability(const io::SimulationConfig& cfg);

// The check above for the configured scheme: explicit Runge–Kutta at dt; MR-OS's RK4
// substeps at `integrator.substep`; α-OS treats the numerical model implicitly (no limit).
// Returns the largest stable step [s] (+infinity if nothing limits it).
double CheckSchemeStability(const io::SimulationConfig& cfg);

// The per-slot stiffness used above (m entries). Unit: [N/m].
std::vector<double> SlotStiffnessForStability(const io::SimulationConfig& cfg);

// Before anything moves: each physical slot's setup against what its transfer system announces
// (TransferSystem::Announce; an emulated bench announces its p0 and limits, a remote bench its
// limits only after connecting, where the client checks them itself):
//   - p0: |setup.p0 − the bench's p0| must not exceed kP0Tolerance × safety.max_increment;
//     else the first command would jump, or the specimen start loaded. The ConfigError names
//     substructures.<slot>.setup.p0, both values (the bench's also in mm) and, for a ratio
//     near 1000, the unit slip;
//   - limits: transfer::CheckLimitsAgainstBench, both directions.
// Throws ConfigError (exit 2). Sends nothing to any bench.
inline constexpr double kP0Tolerance = 0.1;
void CheckPhysicalSlotsBeforeMoving(
    const io::SimulationConfig& cfg,
    const std::vector<std::unique_ptr<substructures::Substructure>>& subs);

}  // namespace hybridtest::app
