#pragma once
// The rules a resume applies to every actuator, one or several (physical_substructure_state.cc,
// multi_actuator_resume.cc; docs/safety.md, "Resuming a run").
#include <algorithm>
#include <cmath>

#include "hybridtest/transfer/safety.h"

namespace hybridtest::substructures {

// The accepted |position − committed| [m] after the re-imposition: a quarter of max_increment.
inline double DefaultResumePositionTolerance(const transfer::SafetyLimits& limits) {
  return 0.25 * limits.max_increment;
}

// The accepted |force − committed| [N]: 1 % of force_hard, and no more than stiffness [N/m]
// times the position tolerance [m] when a stiffness is known (a wider force tolerance would
// accept a position error the position check refuses). stiffness ≤ 0 or NaN: not known.
inline double DefaultResumeForceTolerance(const transfer::SafetyLimits& limits, double stiffness,
                                          double position_tolerance) {
  const double by_limit = 0.01 * limits.force_hard;
  if (std::isfinite(stiffness) && stiffness > 0.0) {
    return std::min(by_limit, stiffness * position_tolerance);
  }
  return by_limit;
}

// Moves from where an actuator is to its committed command, `gap` [m] away: equal moves of at
// most 99.9 % of max_increment [m], so that rounding never pushes one over (a gap of exactly k
// limits takes k + 1 moves); 1 when the gap is within the limit. The last move is the
// re-imposition.
inline int ResumeMoves(double gap, double max_increment) {
  const double g = std::abs(gap);
  if (!(g > max_increment)) return 1;
  return static_cast<int>(std::ceil(g / (0.999 * max_increment)));
}

}  // namespace hybridtest::substructures
