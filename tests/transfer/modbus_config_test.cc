// The `transfer: {type: modbus}` section: defaults, --bench, and errors that name the key.
#include <gtest/gtest.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_config.h"

namespace hybridtest::transfer::modbus {
namespace {

ModbusOptions Parse(const std::string& text, std::optional<std::string> bench = std::nullopt) {
  const YamlInput in = YamlInput::FromText(text, "run.yaml");
  return ParseModbusOptions(in, in.root()["transfer"], "transfer", bench, 3.0);
}

std::string Error(const std::string& text) {
  try {
    Parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ModbusConfig, DefaultsAndOverrides) {
  const ModbusOptions o = Parse("transfer: {type: modbus, host: plc.lab, port: 1502}");
  EXPECT_EQ(o.host, "plc.lab");
  EXPECT_EQ(o.port, 1502);
  EXPECT_EQ(o.unit_id, 1);
  EXPECT_EQ(o.ack_timeout, 3.0);  // the safety section's timeout
  EXPECT_EQ(o.maps[0].command.address, 0);
  const ModbusOptions p = Parse(
      "transfer: {type: modbus, host: plc.lab, unit_id: 3, timeout: 9, poll_interval: 0.01,\n"
      "           plausibility: {position_tolerance: 0.5}, map: {word_order: low_first}}",
      "127.0.0.1:5020");
  EXPECT_EQ(p.host, "127.0.0.1");  // --bench wins
  EXPECT_EQ(p.port, 5020);
  EXPECT_EQ(p.unit_id, 3);
  EXPECT_EQ(p.ack_timeout, 9.0);
  EXPECT_EQ(p.poll_interval, 0.01);
  EXPECT_EQ(p.position_tolerance, 0.5);
  EXPECT_EQ(p.maps[0].word_order, WordOrder::kLowFirst);
}

TEST(ModbusConfig, ErrorsNameTheKeyAndTheFix) {
  EXPECT_NE(Error("transfer: {type: modbus}").find("--bench HOST:PORT"), std::string::npos);
  EXPECT_NE(Error("transfer: {type: modbus, host: h, unit: 1}").find("unit"), std::string::npos);
  EXPECT_NE(Error("transfer: {type: modbus, host: h, unit_id: 300}").find("transfer.unit_id"),
            std::string::npos);
  EXPECT_NE(Error("transfer: {type: modbus, host: h, port: 70000}").find("transfer.port"),
            std::string::npos);
  EXPECT_NE(Error("transfer: {type: modbus, host: h, map: {ack: {address: 2}}}")
                .find("run.yaml:1: transfer.map"),
            std::string::npos);
}

TEST(ModbusConfig, FollowingErrorDefaultsToFourSettlingWindowsAtMostTheSlotsMaxIncrement) {
  const std::string text = "transfer: {type: modbus, host: h}";
  const YamlInput in = YamlInput::FromText(text, "run.yaml");
  SafetyLimits limits;
  limits.max_increment = 0.002;  // [m]
  EXPECT_DOUBLE_EQ(*ParseModbusOptions(in, in.root()["transfer"], "transfer", {}, 3.0, &limits)
                        .following_error, 0.2);  // [mm]: 4 × 0.05 mm, the default profile's unit
  // Capped by the slot's max_increment.
  limits.max_increment = 0.0001;  // [m]
  EXPECT_DOUBLE_EQ(*ParseModbusOptions(in, in.root()["transfer"], "transfer", {}, 3.0, &limits)
                        .following_error, 0.1);
  limits.max_increment = 0.002;
  // Without the slot's limits: the same 0.2 mm.
  EXPECT_DOUBLE_EQ(*Parse(text).following_error, 0.2);
  // A map in metres gets it in metres.
  const YamlInput m = YamlInput::FromText(
      "transfer: {type: modbus, host: h, map: {units: {length: m}}}", "run.yaml");
  EXPECT_DOUBLE_EQ(*ParseModbusOptions(m, m.root()["transfer"], "transfer", {}, 3.0, &limits)
                        .following_error, 0.0002);
  // Given: taken as it is, in the map's unit.
  EXPECT_EQ(*Parse("transfer: {type: modbus, host: h, following_error: 0.5}").following_error, 0.5);
}

TEST(ModbusConfig, FollowingErrorMustBePositiveAndShorterThanTheStroke) {
  EXPECT_NE(Error("transfer: {type: modbus, host: h, following_error: -1}")
                .find("transfer.following_error"),
            std::string::npos);
  EXPECT_NE(Error("transfer: {type: modbus, host: h, following_error: 0}")
                .find("transfer.following_error"),
            std::string::npos);
  // 400 mm on a ±150 mm stroke: probably meant in another unit; it could never trip.
  const std::string error = Error("transfer: {type: modbus, host: h, following_error: 400}");
  EXPECT_NE(error.find("run.yaml:1: transfer.following_error: 400 mm is longer than the whole "
                       "stroke"), std::string::npos) << error;
  EXPECT_NE(error.find("max_increment 5 mm"), std::string::npos) << error;
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
