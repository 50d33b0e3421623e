// RegisterMap: encodings against IEEE 754 bit patterns written out by hand (20.0f is
// 0x41A00000, -1.5f is 0xBFC00000), round trips for every type and order, and the config
// rules (docs/modbus.md).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/register_map.h"

namespace hybridtest::transfer::modbus {
namespace {

std::vector<std::uint16_t> Encode(const RegisterMap& map, const RegisterField& f, double v) {
  std::vector<std::uint16_t> words(f.width());
  EncodeValue(map, f, v, words.data());
  return words;
}

RegisterMap Parse(const std::string& text) {
  const YamlInput in = YamlInput::FromText(text, "map.yaml");
  const std::vector<RegisterMap> maps = ParseRegisterMaps(in, in.root()["map"], "map");
  EXPECT_EQ(maps.size(), 1u) << "a map without `actuators:` is one actuator's";
  return maps.at(0);
}

TEST(ModbusRegisterMap, DefaultProfileIsFloat32BigEndianHighWordFirst) {
  const RegisterMap map;
  EXPECT_EQ(Encode(map, map.command, 20.0), (std::vector<std::uint16_t>{0x41A0, 0x0000}));
  EXPECT_EQ(Encode(map, map.command, -1.5), (std::vector<std::uint16_t>{0xBFC0, 0x0000}));
  EXPECT_EQ(Encode(map, map.sequence, 65535.0), (std::vector<std::uint16_t>{0xFFFF}));
  EXPECT_EQ(map.sequence_modulus(), 65536u);
  EXPECT_EQ(map.units.length_name, "mm");
  EXPECT_DOUBLE_EQ(map.units.metres_per_length_unit, 1e-3);
  // Holding 0–2 in one write; input 0–5 in one read.
  const RegisterBlock write = CommandBlock(map);
  EXPECT_EQ(write.start, 0);
  EXPECT_EQ(write.count, 3);
  const auto reads = ReadoutBlocks({map});
  ASSERT_EQ(reads.size(), 1u);
  EXPECT_EQ(reads[0].table, Table::kInput);
  EXPECT_EQ(reads[0].start, 0);
  EXPECT_EQ(reads[0].count, 6);
  EXPECT_EQ(DescribeField(map.force), "input registers 2–3");
}

TEST(ModbusRegisterMap, WordAndByteOrders) {
  RegisterMap map;
  map.word_order = WordOrder::kLowFirst;  // "CDAB"
  EXPECT_EQ(Encode(map, map.command, -1.5), (std::vector<std::uint16_t>{0x0000, 0xBFC0}));
  map.byte_order = ByteOrder::kLittle;    // "DCBA"
  EXPECT_EQ(Encode(map, map.command, -1.5), (std::vector<std::uint16_t>{0x0000, 0xC0BF}));
  map.word_order = WordOrder::kHighFirst; // "BADC"
  EXPECT_EQ(Encode(map, map.command, -1.5), (std::vector<std::uint16_t>{0xC0BF, 0x0000}));
}

TEST(ModbusRegisterMap, EveryTypeAndOrderRoundTrips) {
  for (auto word : {WordOrder::kHighFirst, WordOrder::kLowFirst}) {
    for (auto byte : {ByteOrder::kBig, ByteOrder::kLittle}) {
      RegisterMap map;
      map.word_order = word;
      map.byte_order = byte;
      const std::pair<ValueType, double> cases[] = {
          {ValueType::kInt16, -1234},   {ValueType::kUint16, 54321},
          {ValueType::kInt32, -123456}, {ValueType::kUint32, 4000000000.0},
          {ValueType::kFloat32, 0.25},  {ValueType::kFloat64, 0.1234567890123}};
      for (const auto& [type, value] : cases) {
        const RegisterField f{Table::kHolding, 10, type, 1.0};
        const auto words = Encode(map, f, value);
        EXPECT_EQ(DecodeValue(map, f, words.data()), value) << static_cast<int>(type);
      }
    }
  }
}

TEST(ModbusRegisterMap, ScaledIntegersRoundAndRefuseWhatDoesNotFit) {
  const RegisterMap map;
  const RegisterField micrometres{Table::kHolding, 0, ValueType::kInt32, 0.001};  // mm per count
  const auto words = Encode(map, micrometres, -12.3456);
  EXPECT_EQ(words, (std::vector<std::uint16_t>{0xFFFF, 0xCFC6}));  // −12346 counts
  EXPECT_NEAR(DecodeValue(map, micrometres, words.data()), -12.346, 1e-12);
  const RegisterField counts{Table::kHolding, 0, ValueType::kInt16, 0.01};
  EXPECT_THROW(Encode(map, counts, 400.0), TransferError);  // 40000 > 32767
  EXPECT_THROW(Encode(map, counts, std::nan("")), TransferError);
}

TEST(ModbusRegisterMap, ParsesAnOverriddenProfile) {
  const RegisterMap map = Parse(R"(
map:
  units: {length: m, force: kN}
  word_order: low_first
  byte_order: little
  command: {address: 100, type: int32, scale: 0.000001}
  sequence: {address: 102}
  position: {table: holding, address: 200, type: int32, scale: 0.000001}
  force: {table: holding, address: 202}
  ack: {table: holding, address: 204}
  status: {table: holding, address: 205, fault_bit: 7, holding_bit: -1}
  lab_time: {address: 10, type: uint32, scale: 0.001}
  enable_coil: 5
  hold_coil: none
)");
  EXPECT_EQ(map.units.force_name, "kN");
  EXPECT_DOUBLE_EQ(map.units.newtons_per_force_unit, 1e3);
  EXPECT_EQ(map.word_order, WordOrder::kLowFirst);
  EXPECT_EQ(map.byte_order, ByteOrder::kLittle);
  EXPECT_EQ(map.command.address, 100);
  EXPECT_EQ(map.command.type, ValueType::kInt32);
  EXPECT_EQ(map.sequence.address, 102);
  EXPECT_EQ(map.position.table, Table::kHolding);
  EXPECT_EQ(map.status_bits.fault, 7);
  EXPECT_EQ(map.status_bits.enabled, 0);
  EXPECT_EQ(map.status_bits.holding, -1);
  ASSERT_TRUE(map.lab_time.has_value());
  EXPECT_EQ(map.lab_time->table, Table::kInput);
  EXPECT_EQ(map.enable_coil, 5);
  EXPECT_FALSE(map.hold_coil.has_value());
  const auto reads = ReadoutBlocks({map});
  ASSERT_EQ(reads.size(), 2u);  // one read per table
  EXPECT_EQ(reads[1].start, 200);
  EXPECT_EQ(reads[1].count, 6);
}

TEST(ModbusRegisterMap, RejectsMapsThatOneRequestCannotServe) {
  const auto message = [](const std::string& text) {
    try {
      Parse(text);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("map: {sequence: {address: 5}}").find("adjacent"), std::string::npos);
  EXPECT_NE(message("map: {force: {address: 1}}").find("overlap"), std::string::npos);
  EXPECT_NE(message("map: {ack: {address: 300}}").find("at most 125"), std::string::npos);
  EXPECT_NE(message("map: {command: {table: input, address: 50}}").find("holding"), std::string::npos);
  EXPECT_NE(message("map: {ack: {type: float32}}").find("uint16 or uint32"), std::string::npos);
  EXPECT_NE(message("map: {command: {type: float16}}").find("float32"), std::string::npos);
  EXPECT_NE(message("map: {word_order: middle}").find("low_first"), std::string::npos);
  EXPECT_NE(message("map: {comand: {address: 0}}").find("comand"), std::string::npos);
  EXPECT_NE(message("map: {hold_coil: 0}").find("enable_coil and hold_coil"), std::string::npos);
  EXPECT_NE(message("map: {units: {length: in}}").find("mm or m"), std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
