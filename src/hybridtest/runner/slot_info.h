#pragma once
// What the schemes may know of a session's substructures (session_stiffness.cc): K0 and the
// largest safe increment per slot of the model (num_slots); a substructure of several slots
// gives its K0 matrix (SlotInfo::k0_matrix). slot_of: the model slots each substructure serves.
#include <memory>
#include <vector>

#include "hybridtest/schemes/scheme_config.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

schemes::SlotInfo SlotInfoOf(const std::vector<std::unique_ptr<substructures::Substructure>>& subs,
                             const std::vector<std::vector<int>>& slot_of, int num_slots);

}  // namespace hybridtest::runner
