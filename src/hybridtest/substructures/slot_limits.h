#pragma once
// SlotLimits: safety limits on the slots of a substructure of several actuators, on top of
// every actuator's own (transfer/safety.h). The run config's `safety: {slots: {...}}`:
//
//   max_displacement (m) [m]   |d_i| beyond it: the trial is refused before any actuator
//                              moves, and every actuator holds;
//   max_force        (m) [N]   |r_i| beyond it (r = J(d)ᵀ f, from the measured forces): every
//                              actuator holds and the test stops.
//
// +inf: no limit on that slot. The stop (SafetyStop, limit "slot_max_displacement" or
// "slot_max_force") names the slot.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace hybridtest::substructures {

struct SlotLimits {
  std::vector<std::string> names;   // (m) the slots, for messages
  Eigen::VectorXd max_displacement;  // (m) [m], each > 0 (+inf: none)
  Eigen::VectorXd max_force;         // (m) [N], each > 0 (+inf: none)
};

}  // namespace hybridtest::substructures
