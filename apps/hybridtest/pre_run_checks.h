#pragma once
// Checks made before a run starts, so that a slip (a step beyond the scheme's stability limit,
// a run that would fill the disk) is refused with exit 2 instead of producing diverged results
// or failing hours later.
#include <string>

#include "hybridtest/io/config.h"

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

}  // namespace hybridtest::app
