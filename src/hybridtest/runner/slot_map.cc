// See slot_map.h.
#include "hybridtest/runner/slot_map.h"

namespace hybridtest::runner {

SlotMap MakeSlotMap(const std::vector<std::unique_ptr<substructures::Substructure>>& subs,
                    const std::vector<std::string>& names,
                    const std::vector<std::vector<int>>& slot_of,
                    const std::vector<std::string>& slot_names) {
  SlotMap map;
  map.slots.resize(slot_names.size());
  for (std::size_t i = 0; i < slot_names.size(); ++i) map.slots[i].name = slot_names[i];
  for (std::size_t s = 0; s < subs.size(); ++s) {
    SlotMap::Block block;
    block.name = names[s];
    block.physical = subs[s]->is_physical();
    block.slots = slot_of[s];
    block.first_actuator = map.num_actuators;
    block.num_actuators = subs[s]->num_actuators();
    map.num_actuators += block.num_actuators;
    for (std::size_t k = 0; k < block.slots.size(); ++k) {
      SlotMap::Slot& slot = map.slots[static_cast<std::size_t>(block.slots[k])];
      slot.substructure = static_cast<int>(s);
      slot.index = static_cast<int>(k);
      for (int a = 0; a < block.num_actuators; ++a) slot.actuators.push_back(block.first_actuator + a);
    }
    map.substructures.push_back(std::move(block));
  }
  return map;
}

}  // namespace hybridtest::runner
