#pragma once
// SlotMap: which substructure serves which slot of the model, through which actuators — public
// data of a built Session (MuJoCo's `jnt_dofadr`/`actuator_trnid` habit), for everything above
// the builders that needs it: the delay check and the paced loop of a real-time run, `plan`,
// `probe`, resume, the bench record and the stop record. Nobody above the builders casts a
// substructure or a transfer system to its concrete type; what it needs is here, or behind a
// virtual of Substructure (substructure.h) or TransferSystem (transfer_system.h).
//
//   slots[i]          slot i of the model (the model's order): its name, the substructure that
//                     serves it, its place among that substructure's slots, and the actuators
//                     (indices into the run's actuator order: the journal's channel groups) of
//                     that substructure, every one of which may move it
//   substructures[s]  substructure s (the spec's order): its name, physical or not, the model
//                     slots it serves (its order), and its actuators first_actuator ..
//                     first_actuator + num_actuators − 1
//
// n = m = 1 is the ordinary case: one slot, one substructure, one actuator (or none).
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/substructures/substructure.h"

namespace hybridtest::runner {

struct SlotMap {
  struct Slot {
    std::string name;            // the model's slot name
    int substructure = 0;        // index into substructures
    int index = 0;               // place among its substructure's slots (0-based)
    std::vector<int> actuators;  // run actuator indices (empty: numerical)
  };
  struct Block {
    std::string name;            // the spec's name (its journal channels' prefix)
    bool physical = false;
    std::vector<int> slots;      // model slot indices, in the substructure's order
    int first_actuator = 0;      // its first actuator in the run's order
    int num_actuators = 0;       // 0 for a numerical substructure
  };
  std::vector<Slot> slots;
  std::vector<Block> substructures;
  int num_actuators = 0;  // every actuator of the run

  // The substructure serving model slot i.
  const Block& block_of(int slot) const {
    return substructures[static_cast<std::size_t>(slots[static_cast<std::size_t>(slot)].substructure)];
  }
};

// The map of built substructures `subs` with their spec names `names` serving the model slots
// `slot_of[s]` (substructures::SlotIndices) of the model's `slot_names`.
SlotMap MakeSlotMap(const std::vector<std::unique_ptr<substructures::Substructure>>& subs,
                    const std::vector<std::string>& names,
                    const std::vector<std::vector<int>>& slot_of,
                    const std::vector<std::string>& slot_names);

}  // namespace hybridtest::runner
