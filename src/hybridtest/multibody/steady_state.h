#pragma once
// A steady state: the values of chosen coordinates (the "free" ones) at which the speeds'
// rates vanish, u̇(t, x) = 0, with the other coordinates and the independent speeds held (a
// rotor at a set speed, a governor spinning at Ω, a sprung pendulum under gravity). For a
// constrained model the dependent coordinates and speeds are reassembled (AssembleState) at
// every iterate, so the equations hold on the constraint manifold.
//
// The equations are the speed rates u̇_k (residual R: all n, or those of the speeds not in
// SteadyStateOptions::driven_speeds, which a drive holds); the unknowns the n_f free
// coordinates. Gauss–Newton: the step δ solves min |R + G δ|₂ (least squares when there are
// more equations than unknowns; a column-pivoted QR, rank-revealing), with
//   G = (J T)[rows of R, free columns],  J = ∂ẋ/∂x exact (AutoDiff, LinearizeConstrained),
// T the manifold's tangent (the chain rule through the dependent q and u). A backtracking line
// search on |R|₂ (Armijo, halving down to 2⁻²⁰) damps the step; a trial state the constraints
// cannot reach is a failed trial. Slots are closed by r = k d(q), as in CalcModes.
//
// Converged: max_k |u̇_k| ≤ tolerance (absolute, in the speed rates' own units: m/s², rad/s²).
// Not converged (the result says so, with a message naming the residual, the largest speed
// rate and what to try): the iteration limit, a step that no longer reduces |R| (a least
// |u̇| that is not zero: no steady state near the start), or a free coordinate that no speed
// rate depends on (nothing restores it). Cost per iteration: one exact Jacobian (2n + nz
// directions) and a few right-hand sides.
#include <string>
#include <vector>

#include "hybridtest/multibody/assembly.h"

namespace hybridtest::multibody {

// The most Gauss–Newton iterations a front may ask for (`modes --steady-iterations`,
// Python's modes(max_iterations=)): one bound for both.
inline constexpr int kMaxSteadyIterations = 10000;

struct SteadyStateOptions {
  double tolerance = 1e-10;   // on max |u̇_k| [the speed rates' units]
  int max_iterations = 50;    // 1 to kMaxSteadyIterations
  // Speeds held by a drive (a motor keeps the rotor at its speed): their rates are left out
  // of the equations (indices in u). Empty: every speed's rate must vanish.
  std::vector<int> driven_speeds;
};

struct SteadyState {
  Eigen::VectorXd x;                   // (2n + nz) the last iterate, assembled
  std::vector<int> free_coordinates;   // indices in q
  std::vector<int> driven_speeds;      // indices in u (their rates left out)
  int iterations = 0;                  // Gauss–Newton steps taken
  double residual = 0.0;               // max_k |u̇_k| at x (k not driven) [the rates' units]
  int worst_speed = -1;                // the k (index in u) of that largest |u̇_k|
  bool converged = false;
  std::string message;                 // empty when converged; else why and what to try
};

// How far (t, x) is from a steady state: max_k |u̇_k| over every speed (x assembled first,
// slots closed by r = k d(q) as in CalcModes). Fills residual and worst_speed.
struct SpeedRateResidual {
  double residual = 0.0;   // max_k |u̇_k| [the rates' units]
  int worst_speed = -1;    // its k (index in u); -1 for a model without speeds
};
SpeedRateResidual CalcSpeedRateResidual(const Model& model, double t, const Eigen::VectorXd& x,
                                        const std::vector<double>& slot_stiffness);

// The unit of speed k's rate: "rad/s²" for "rad/s", "m/s²" for "m/s", else unit + "/s".
std::string SpeedRateUnit(const Model& model, int k);

// From (t, x) (assembled first), with the coordinates `free_coordinates` (indices in q,
// independent ones: a dependent coordinate is refused) solved for u̇ = 0 and the slots closed
// by r = k d(q) (k = slot_stiffness, one per slot; empty: r = 0). Throws ModelError for a bad
// list of free coordinates or a start the constraints cannot reach; a search that does not
// converge returns converged = false with the message.
SteadyState FindSteadyState(const Model& model, double t, const Eigen::VectorXd& x,
                            const std::vector<int>& free_coordinates,
                            const std::vector<double>& slot_stiffness,
                            const SteadyStateOptions& options = {});

}  // namespace hybridtest::multibody
