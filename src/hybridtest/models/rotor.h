#pragma once
// The paper's wind-turbine rotor (Section 2, Table 1; see shared PAPER-NOTES for the checked
// facts). N blades, each a point mass m_b at its tip P_i = O + l_b b̂_ix + q_i b̂_iy, on a hub
// of inertia I_g about ẑ with generator damping d_g. Blade frames B_i are the hub frame H
// turned by the azimuth ψ_i = 2π(i−1)/N; H is N turned by q_{N+1} about ẑ.
//
// Coordinates: q_i [m] tip deflection of blade i (i = 1..N), q_{N+1} [rad] hub angle; u = q̇.
// Loads (ρ(t) = 1 − e^{−t/t0}, the ramp of Eq. 12):
//   at P_i:  −r_i b̂_iy + m_b ρ g n̂_x + ρ f_w b̂_iy,   r_i = r_i^s + ζ_b m_b u_i   (Eq. 9, 11)
//   on H:    (−d_g u_{N+1} + Σ_i r_i l_b) ẑ                                      (Eq. 10)
// Restoring-force slots r1..rN: the static restoring force r_i^s [N] of blade i, seeing the
// displacement q_i; numerically r_i^s = k_b q_i. M and g are derived by the engine, never
// transcribed from Eq. (19)–(20), which contain sign errors.
//
// Parameters (SI; defaults from Table 1): l_b, m_b, zeta_b, k_b, f_w, I_g, d_g, g, t0, and per
// blade i the overrides blade<i>.l_b, .m_b, .zeta_b, .k_b, .f_w, .psi.
#include "hybridtest/models/catalogue.h"

namespace hybridtest::models {

ParameterSet RotorDefaultParameters(int blades);
BuiltModel BuildRotor(int blades, const ParameterSet& parameters);

}  // namespace hybridtest::models
