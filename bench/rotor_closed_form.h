#pragma once
// A hand-written closed form of the rotor's right-hand side, the reference the Kane engine is
// benchmarked against (bench_rotor_rhs.cc) and cross-checked with (tests/models/
// rotor_closed_form_test.cc). Three blades, Table 1 parameters, azimuths ψ_i = 2π(i−1)/3, the
// static restoring forces r^s given.
//
// Derived from the verified engine's structure (models/rotor.h), not from the paper's
// Eq. (19)–(20), which contain sign errors. With φ_i = q4 + ψ_i, ρ(t) = 1 − e^{−t/t0},
// θ̇ = u4 and c = ζ_b m_b, in the convention M u̇ = g (kane.h):
//
//   M = ⎡ m_b   0    0   m_b l_b ⎤      M_44 = I_g + Σ_i m_b (l_b² + q_i²)
//       ⎢  0   m_b   0   m_b l_b ⎥
//       ⎢  0    0   m_b  m_b l_b ⎥
//       ⎣ m_b l_b (×3)     M_44  ⎦
//
//   g_i = −(r_i + c u_i) + ρ f_w − m_b g ρ sin φ_i + m_b θ̇² q_i                  (i = 1..3)
//   g_4 = −d_g θ̇ + Σ_i [ l_b (ρ f_w − m_b g ρ sin φ_i + m_b θ̇² q_i)
//                        − q_i m_b (g ρ cos φ_i + 2 u_i θ̇ + l_b θ̇²) ]
//
// (the blades' root reactions l_b (r_i + c u_i) on the hub cancel their moment about the hub
// axis, so they are absent from g_4). Then u̇ = M⁻¹ g by a fixed-size 4×4 Cholesky (LLT), the
// way one solves a written-out SPD mass matrix; ẋ = [u; u̇].
//
// RotorRhsArrow() solves the same system through the arrow structure instead (Schur
// complement s = M_44 − Σ (m_b l_b)²/m_b = I_g + Σ m_b q_i²), for information.
#include <Eigen/Core>

namespace hybridtest::bench {

using RotorState = Eigen::Matrix<double, 8, 1>;  // x = [q1 q2 q3 θ; u1 u2 u3 θ̇] (SI)

// Table 1 of the paper (the engine's defaults, models/rotor.cc).
struct RotorParameters {
  double l_b = 0.5;      // [m]
  double m_b = 1.96;     // [kg]
  double zeta_b = 1.0;   // [1/s]
  double f_w = 100.0;    // [N]
  double I_g = 0.1;      // [kg·m²]
  double d_g = 100.0;    // [N·m·s]
  double g = 9.82;       // [m/s²]
  double t0 = 0.5;       // [s]
};

// M (4×4) and g (4) at (t, x, r); r = r^s [N] (3).
void CalcRotorMassMatrix(const RotorParameters& p, const RotorState& x,
                         Eigen::Matrix4d& M);
void CalcRotorForcing(const RotorParameters& p, double t, const RotorState& x,
                      const Eigen::Vector3d& r, Eigen::Vector4d& g);

// ẋ (8) at (t, x, r): M and g as above, Cholesky solve.
void CalcRotorRhs(const RotorParameters& p, double t, const RotorState& x,
                  const Eigen::Vector3d& r, RotorState& xdot);

// The same ẋ with the arrow-structure solve instead of Cholesky.
void CalcRotorRhsArrow(const RotorParameters& p, double t, const RotorState& x,
                       const Eigen::Vector3d& r, RotorState& xdot);

}  // namespace hybridtest::bench
