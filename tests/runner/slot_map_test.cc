// The slot map a Session publishes (runner/slot_map.h): which substructure serves which slot of
// the model through which actuators, for one actuator per slot and for one specimen on two
// actuators serving two slots.
#include "hybridtest/runner/slot_map.h"

#include <gtest/gtest.h>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"

namespace hybridtest::runner {
namespace {

const std::string kSource = HYBRIDTEST_SOURCE_DIR;

Session Open(const std::string& config) {
  io::RunSpec spec = io::LoadRunSpec(kSource + config);
  spec.output.files = false;
  spec.quiet = true;
  return Session(std::move(spec));
}

TEST(SlotMap, OneSpecimenOnTwoActuatorsServesBothSlots) {
  const Session session = Open("/examples/06_blade_two_actuators/emulated.yaml");
  const SlotMap& map = session.slot_map();
  ASSERT_EQ(map.slots.size(), 2u);
  ASSERT_EQ(map.substructures.size(), 1u);
  EXPECT_EQ(map.num_actuators, 2);
  EXPECT_EQ(map.slots[0].name, "r_flap");
  EXPECT_EQ(map.slots[1].name, "r_edge");
  for (int i = 0; i < 2; ++i) {
    const SlotMap::Slot& slot = map.slots[static_cast<std::size_t>(i)];
    EXPECT_EQ(slot.substructure, 0);
    EXPECT_EQ(slot.index, i);
    EXPECT_EQ(slot.actuators, (std::vector<int>{0, 1}));
    EXPECT_EQ(&map.block_of(i), &map.substructures[0]);
  }
  const SlotMap::Block& block = map.substructures[0];
  EXPECT_EQ(block.name, "blade1");
  EXPECT_TRUE(block.physical);
  EXPECT_EQ(block.slots, (std::vector<int>{0, 1}));
  EXPECT_EQ(block.first_actuator, 0);
  EXPECT_EQ(block.num_actuators, 2);
  // The substructure's transfer system is reached through the interface.
  const transfer::TransferSystem* t = session.substructures()[0]->transfer_system();
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->num_actuators(), 2);
  EXPECT_FALSE(t->can_run_paced());
}

TEST(SlotMap, ANumericalBlockHasNoActuators) {
  const Session session = Open("/examples/06_blade_two_actuators/dummy.yaml");
  const SlotMap& map = session.slot_map();
  ASSERT_EQ(map.substructures.size(), 1u);
  EXPECT_FALSE(map.substructures[0].physical);
  EXPECT_EQ(map.num_actuators, 0);
  EXPECT_TRUE(map.slots[0].actuators.empty());
  EXPECT_EQ(session.substructures()[0]->transfer_system(), nullptr);
}

}  // namespace
}  // namespace hybridtest::runner
