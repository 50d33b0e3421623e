#pragma once
// Linear stability of explicit Runge–Kutta schemes: the largest step that keeps every mode of
// a linearised system from growing.
//
// Applied to the test equation y' = λ y, one step of an explicit tableau (a, b) gives
// y_{n+1} = R(hλ) y_n with the stability polynomial (Hairer & Wanner, Solving ODEs II, §IV.2)
//
//   R(z) = 1 + Σ_{k=1}^{s} β_k z^k,   β_k = bᵀ a^{k−1} 𝟙                 (degree ≤ s)
//
// (β_k = 1/k! for k ≤ p: heun R = 1 + z + z²/2; rk4 adds z³/6 + z⁴/24). A step h is stable
// for the mode λ when |R(hλ)| ≤ 1. For a linearised system ẋ ≈ J x, the modes are the
// eigenvalues of J, and the largest stable step is the smallest, over the modes, of the first
// h along the ray h·λ (h > 0) where |R(hλ)| exceeds 1.
//
// Precisely, a step is accepted while |R(hλ)| ≤ max(1, |e^{hλ}|) + kNeutralTolerance: a
// decaying mode may not grow (beyond 1e-6 per step, which only matters for a nearly undamped
// mode), and a mode that does not decay (Re λ ≥ 0: an undamped or unstable mode) may not grow
// faster than it does itself by more than 1e-6 per step. Modes with |λ| below kNegligibleRate
// are ignored (rigid-body modes such as a free rotation).
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "hybridtest/integrators/butcher_tableau.h"

namespace hybridtest::integrators {

inline constexpr double kNeutralTolerance = 1e-6;  // spurious growth per step [-]
inline constexpr double kNegligibleRate = 1e-9;    // |λ| ignored below this. Unit: [1/s].

// β_0 = 1, β_1, ..., β_s of R(z) (s + 1 entries) for an explicit tableau.
Eigen::VectorXd StabilityPolynomial(const ButcherTableau& tableau);

// R(z) from its coefficients.
std::complex<double> EvalStabilityPolynomial(const Eigen::VectorXd& beta, std::complex<double> z);

// Largest stable step for the single mode λ [1/s]: +infinity if every step is stable (e.g. a
// negligible λ). Unit: [s].
double LargestStableStep(const Eigen::VectorXd& beta, std::complex<double> lambda);

// Largest stable step for all `eigenvalues` [1/s]; +infinity if there is none to limit it.
// Unit: [s]. `limiting`, if not null, receives the eigenvalue that sets the limit.
double LargestStableStep(const ButcherTableau& tableau,
                         const std::vector<std::complex<double>>& eigenvalues,
                         std::complex<double>* limiting = nullptr);

}  // namespace hybridtest::integrators
