#pragma once
// Test helper: the trial of a substructure of one slot, as a number (Substructure::Trial takes
// the slot vectors of every size).
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::substructures::testing {

// r [N] at d [m] of a one-slot substructure.
inline double TrialOne(Substructure& s, double d, const TrialContext& context) {
  double r = 0.0;
  s.Trial({&d, 1}, {&r, 1}, context);
  return r;
}

}  // namespace hybridtest::substructures::testing
