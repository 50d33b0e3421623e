// The register map of several actuators (register_map.h): the strided and the explicit
// form, the requests they make, and every bad input named by its key path with the fix.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_config.h"
#include "hybridtest/transfer/modbus/register_map.h"

namespace hybridtest::transfer::modbus {
namespace {

std::vector<RegisterMap> Parse(const std::string& text) {
  const YamlInput in = YamlInput::FromText(text, "run.yaml");
  return ParseRegisterMaps(in, in.root()["map"], "transfer.map");
}

std::string Error(const std::string& text) {
  try {
    Parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

// The float64 profile of the test controller (modbus_server.py --type float64).
const std::string kFloat64 = R"(
map:
  command: {address: 0, type: float64}
  sequence: {address: 4}
  position: {address: 0, type: float64}
  force: {address: 4, type: float64}
  ack: {address: 8}
  status: {address: 9}
)";

TEST(ModbusMultiMap, WithoutActuatorsKeysTheMapIsTheOneActuatorMap) {
  const auto maps = Parse("map: {command: {address: 10}, sequence: {address: 12}}");
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0].command.address, 10);
  ASSERT_EQ(Parse("other: 1").size(), 1u);  // no map: the default profile
}

TEST(ModbusMultiMap, ActuatorsAlonePacksTheDefaultProfileOneBlockAfterTheOther) {
  const auto maps = Parse("map: {actuators: 2}");
  ASSERT_EQ(maps.size(), 2u);
  const RegisterMap& b = maps[1];
  EXPECT_EQ(b.command.address, 3);  // holding 0–2 are actuator 1's
  EXPECT_EQ(b.sequence.address, 5);
  EXPECT_EQ(b.position.address, 6);  // input 0–5 are actuator 1's
  EXPECT_EQ(b.force.address, 8);
  EXPECT_EQ(b.ack.address, 10);
  EXPECT_EQ(b.status->address, 11);
  EXPECT_EQ(b.enable_coil, 2);
  EXPECT_EQ(b.hold_coil, 3);
  // Contiguous: one write of holding 0–5 and one read of input 0–11 serve both.
  const auto writes = CommandWrites(maps);
  ASSERT_EQ(writes.size(), 1u);
  EXPECT_EQ(writes[0].block.start, 0);
  EXPECT_EQ(writes[0].block.count, 6);
  EXPECT_EQ(writes[0].actuators, (std::vector<int>{0, 1}));
  const auto reads = ReadoutBlocks(maps);
  ASSERT_EQ(reads.size(), 1u);
  EXPECT_EQ(reads[0].start, 0);
  EXPECT_EQ(reads[0].count, 12);
  EXPECT_EQ(HoldCoils(maps), (std::vector<int>{1, 3}));
  EXPECT_EQ(EnableCoils(maps), (std::vector<int>{0, 2}));
}

TEST(ModbusMultiMap, StrideWithGapsWritesOncePerActuatorAndSplitsLongReads) {
  const auto maps = Parse(kFloat64 + "  actuators: 3\n  stride: {holding: 16, input: 60, coils: 0}\n");
  ASSERT_EQ(maps.size(), 3u);
  EXPECT_EQ(maps[2].command.address, 32);
  EXPECT_EQ(maps[2].command.type, ValueType::kFloat64);
  EXPECT_EQ(maps[2].ack.address, 128);
  const auto writes = CommandWrites(maps);
  ASSERT_EQ(writes.size(), 3u);  // holding 0–4, 16–20, 32–36: not adjacent
  EXPECT_EQ(writes[1].block.start, 16);
  EXPECT_EQ(writes[1].block.count, 5);
  // Input 0–9, 60–69, 120–129: the first two in one read (70 registers), the third apart (an
  // actuator's fields are never split between two reads).
  const auto reads = ReadoutBlocks(maps);
  ASSERT_EQ(reads.size(), 2u);
  EXPECT_EQ(reads[0].start, 0);
  EXPECT_EQ(reads[0].count, 70);
  EXPECT_EQ(reads[1].start, 120);
  EXPECT_EQ(reads[1].count, 10);
  // coils: 0 shares one enable and one hold coil.
  EXPECT_EQ(HoldCoils(maps), (std::vector<int>{1}));
  EXPECT_EQ(EnableCoils(maps), (std::vector<int>{0}));
}

TEST(ModbusMultiMap, PerActuatorFieldsReplaceTheStridedOnes) {
  const auto maps = Parse(R"(
map:
  per_actuator:
    - {}
    - command: {address: 100}
      sequence: {address: 102}
      position: {table: holding, address: 200, type: int32, scale: 0.001}
      force: {address: 50}
      ack: {address: 52}
      status: {address: 53, fault_bit: 7}
      enable_coil: 10
      hold_coil: 11
)");
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].command.address, 0);
  const RegisterMap& b = maps[1];
  EXPECT_EQ(b.command.address, 100);
  EXPECT_EQ(b.command.type, ValueType::kFloat32);  // a field's keys start from the strided one
  EXPECT_EQ(b.position.table, Table::kHolding);
  EXPECT_EQ(b.position.type, ValueType::kInt32);
  EXPECT_EQ(b.status_bits.fault, 7);
  EXPECT_EQ(maps[0].status_bits.fault, 1);
  EXPECT_EQ(b.hold_coil, 11);
  EXPECT_EQ(CommandWrites(maps).size(), 2u);
  const auto reads = ReadoutBlocks(maps);  // input 0–5 and 50–53 in one; holding 200–201
  ASSERT_EQ(reads.size(), 2u);
  EXPECT_EQ(reads[0].count, 54);
  EXPECT_EQ(reads[1].table, Table::kHolding);
  EXPECT_EQ(reads[1].start, 200);
}

TEST(ModbusMultiMap, TheLabTimeIsTheControllersAndReadOnce) {
  const auto maps = Parse("map: {actuators: 2, lab_time: {address: 20, type: uint32, scale: 0.001}}");
  ASSERT_TRUE(maps[0].lab_time.has_value());
  EXPECT_FALSE(maps[1].lab_time.has_value());
  EXPECT_EQ(ReadoutBlocks(maps)[0].count, 22);
}

TEST(ModbusMultiMap, BadInputsNameTheKeyAndTheFix) {
  // A stride narrower than a block: the two actuators share registers.
  std::string e = Error("map: {actuators: 2, stride: {holding: 2}}");
  EXPECT_NE(e.find("run.yaml:1: transfer.map"), std::string::npos) << e;
  EXPECT_NE(e.find("actuator 1's sequence (holding register 2)"), std::string::npos) << e;
  EXPECT_NE(e.find("actuator 2's command (holding registers 2–3)"), std::string::npos) << e;
  EXPECT_NE(e.find("transfer.map.stride"), std::string::npos) << e;
  // An explicit field on another actuator's register.
  e = Error("map:\n  per_actuator:\n    - {}\n    - {force: {address: 4}}\n");
  EXPECT_NE(e.find("actuator 1's ack (input register 4)"), std::string::npos) << e;
  EXPECT_NE(e.find("actuator 2's force"), std::string::npos) << e;
  // Within one actuator's explicit entry: named by the entry's key path.
  e = Error("map:\n  per_actuator:\n    - {}\n    - {sequence: {address: 9}}\n");
  EXPECT_NE(e.find("transfer.map.per_actuator[1] (actuator 2)"), std::string::npos) << e;
  EXPECT_NE(e.find("adjacent"), std::string::npos) << e;
  // Counts.
  e = Error("map: {actuators: 0}");
  EXPECT_NE(e.find("transfer.map.actuators"), std::string::npos) << e;
  e = Error("map: {actuators: 2, per_actuator: [{}, {}, {}]}");
  EXPECT_NE(e.find("transfer.map.per_actuator"), std::string::npos) << e;
  EXPECT_NE(e.find("3 entries for `actuators: 2`"), std::string::npos) << e;
  e = Error("map: {per_actuator: []}");
  EXPECT_NE(e.find("one mapping per actuator"), std::string::npos) << e;
  // Keys that are the controller's, not an actuator's; typos.
  e = Error("map: {per_actuator: [{}, {units: {length: m}}]}");
  EXPECT_NE(e.find("transfer.map.per_actuator[1]"), std::string::npos) << e;
  EXPECT_NE(e.find("units"), std::string::npos) << e;
  e = Error("map: {actuators: 2, stride: {holdings: 3}}");
  EXPECT_NE(e.find("transfer.map.stride"), std::string::npos) << e;
  EXPECT_NE(e.find("holdings"), std::string::npos) << e;
  e = Error("map: {actuators: 2, stride: {input: -6}}");
  EXPECT_NE(e.find("transfer.map.stride.input"), std::string::npos) << e;
  // A coil that is one actuator's hold and another's enable.
  e = Error("map: {actuators: 2, stride: {coils: 1}}");
  EXPECT_NE(e.find("coil 1 is actuator 2's enable_coil and actuator 1's hold_coil"),
            std::string::npos) << e;
  // The lab time inside another actuator's block.
  e = Error("map: {actuators: 2, lab_time: {address: 6, type: uint32}}");
  EXPECT_NE(e.find("lab_time"), std::string::npos) << e;
  EXPECT_NE(e.find("actuator 2's position"), std::string::npos) << e;
  // Strided past the last address.
  e = Error("map: {actuators: 3, stride: {holding: 40000}}");
  EXPECT_NE(e.find("actuator 3: actuator 1's fields moved by 2 × the stride"), std::string::npos)
      << e;
  EXPECT_NE(e.find("command.address = 80000"), std::string::npos) << e;
}

TEST(ModbusMultiMap, TheTransferSectionGivesATransferOfNActuators) {
  const YamlInput in = YamlInput::FromText(
      "transfer: {type: modbus, host: plc.lab, map: {actuators: 2, stride: {coils: 0}}}",
      "run.yaml");
  const ModbusOptions o = ParseModbusOptions(in, in.root()["transfer"], "transfer", {}, 3.0);
  ASSERT_EQ(o.maps.size(), 2u);
  const ModbusTransfer transfer(o);
  EXPECT_EQ(transfer.num_actuators(), 2);
  EXPECT_NE(transfer.Describe().find("2 actuators; commands at holding registers 0–1, 3–4"),
            std::string::npos) << transfer.Describe();
  // One actuator: one map, of the default profile.
  const YamlInput one = YamlInput::FromText("transfer: {type: modbus, host: plc.lab}", "run.yaml");
  const ModbusOptions p = ParseModbusOptions(one, one.root()["transfer"], "transfer", {}, 3.0);
  ASSERT_EQ(p.maps.size(), 1u);
  EXPECT_EQ(p.maps[0].command.address, RegisterMap{}.command.address);
  EXPECT_EQ(ModbusTransfer(p).num_actuators(), 1);
  // The following error: one for all, or one per actuator.
  const auto following = [](const std::string& value) {
    const YamlInput y = YamlInput::FromText(
        "transfer: {type: modbus, host: h, following_error: " + value + ", map: {actuators: 2}}",
        "run.yaml");
    return ParseModbusOptions(y, y.root()["transfer"], "transfer", {}, 3.0);
  };
  EXPECT_EQ(following("3").following_error, 3.0);
  EXPECT_TRUE(following("3").following_errors.empty());
  EXPECT_EQ(following("[3, 1.5]").following_errors, (std::vector<double>{3.0, 1.5}));
  try {
    following("[3, 1.5, 2]");
    ADD_FAILURE() << "three limits for two actuators";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("run.yaml:1: transfer.following_error: 3 values for 2 "
                                         "actuators: give one limit per actuator"), std::string::npos) << e.what();
  }
  EXPECT_THROW(following("[3, -1]"), ConfigError);
  // A hand-built options whose maps disagree on the units is refused.
  ModbusOptions bad = o;
  bad.maps[1].units.length_name = "m";
  EXPECT_THROW(ModbusTransfer{bad}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
