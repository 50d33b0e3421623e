// The settled-reading check (transfer/safety_settled_reading.h) on its own and in a Modbus
// transfer against the pymodbus test controller: the following error defaults from the
// settling window (a 1.5 mm offset on actuator 2 of two now stops), and a controller that
// acknowledges before it updates its data is caught as a stale acknowledgement. The Modbus
// cases are skipped, with a message, when python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/modbus/modbus_config.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_settled_reading.h"
#include "transfer/modbus_server_process.h"
#include "transfer/modbus_test_support.h"

namespace hybridtest::transfer {
namespace {

using modbus::ModbusOptions;
using modbus::ModbusTransfer;
using testing::ModbusServerProcess;

SettledReadingCheck::Source MmSource() {
  SettledReadingCheck::Source s;
  s.unit = "mm";
  s.metres_per_unit = 1e-3;
  s.answered = [](std::size_t k) { return "The bench (actuator " + std::to_string(k + 1) + ")"; };
  s.after = "it holds";
  s.following_key = "following_error";
  s.settle_key = "settle_tolerance";
  return s;
}

// The SafetyStop that `f` throws; fails the test if there is none.
template <class F>
SafetyStop StopOf(F&& f) {
  try {
    f();
  } catch (const SafetyStop& e) {
    return e;
  }
  ADD_FAILURE() << "no SafetyStop";
  return SafetyStop("none", 0, 0, 0, 0, {}, "");
}

TEST(SettledReading, TheDefaultFollowingErrorIsFourSettlingWindowsAtMostTheIncrement) {
  EXPECT_DOUBLE_EQ(DefaultFollowingError(0.05, 5.0), 0.2);  // mm
  EXPECT_DOUBLE_EQ(DefaultFollowingError(0.05, 0.1), 0.1);  // capped by max_increment
  EXPECT_EQ(InBenchUnit(kDefaultSettleTolerance, 1e-3), 0.05);  // not 0.049999999999999996
  EXPECT_EQ(InBenchUnit(SafetyLimits{}.max_increment, 1e-3), 5.0);
  EXPECT_THROW(SettledReadingCheck({{0.0, 0.05}}), ConfigError);
  EXPECT_THROW(SettledReadingCheck({{0.2, -1.0}}), ConfigError);
}

TEST(SettledReading, ASettledActuatorPassesAndAnOffsetBeyondTheLimitStops) {
  SettledReadingCheck check({{0.2, 0.05}, {0.2, 0.05}});
  const std::array<double, 2> c1{20.0, 30.0}, p1{20.04, 29.97};  // within the settling window
  check.Check(c1, p1, MmSource());
  const std::array<double, 2> c2{21.0, 31.0}, p2{21.0, 32.5};    // actuator 2: 1.5 mm off
  const SafetyStop stop = StopOf([&] { check.Check(c2, p2, MmSource()); });
  EXPECT_EQ(stop.limit(), "following_error");
  EXPECT_NEAR(stop.value(), 1.5e-3, 1e-12);
  EXPECT_NEAR(stop.limit_value(), 0.2e-3, 1e-12);
  const std::string what = stop.what();
  EXPECT_NE(what.find("The bench (actuator 2) but measured position 32.5 mm"), std::string::npos)
      << what;
  EXPECT_NE(what.find("> following_error 0.2 mm"), std::string::npos) << what;
}

TEST(SettledReading, AReadingThatDidNotFollowAMovedCommandIsAStaleAcknowledgement) {
  SettledReadingCheck check({{5.0, 0.05}});
  const double c1 = 20.0, p1 = 20.01;
  check.Check({&c1, 1}, {&p1, 1}, MmSource());
  // The same command again (a resume's re-imposition), the same reading: not stale.
  check.Check({&c1, 1}, {&p1, 1}, MmSource());
  // A move within two settling windows may leave the reading where it was.
  const double c2 = 20.09;
  check.Check({&c2, 1}, {&p1, 1}, MmSource());
  // A 0.5 mm move answered with the previous position, bit for bit: stale, although well
  // inside the 5 mm following error.
  const double c3 = 20.59;
  const SafetyStop stop = StopOf([&] { check.Check({&c3, 1}, {&p1, 1}, MmSource()); });
  EXPECT_EQ(stop.limit(), "stale_acknowledgement");
  EXPECT_NEAR(stop.value(), 0.5e-3, 1e-12);
  EXPECT_NEAR(stop.limit_value(), 0.1e-3, 1e-12);
  EXPECT_NE(std::string(stop.what()).find("is the one of the previous command 20.09 mm"),
            std::string::npos) << stop.what();
  // After Reset (a new Activate) there is no previous reading to compare with.
  check.Reset();
  check.Check({&c3, 1}, {&p1, 1}, MmSource());  // 0.58 mm off: within 5 mm
}

TEST(SettledReading, TheModbusConfigDerivesTheFollowingErrorFromTheSettlingWindow) {
  const auto parse = [](const std::string& text, const SafetyLimits* limits = nullptr) {
    const YamlInput in = YamlInput::FromText(text, "run.yaml");
    return modbus::ParseModbusOptions(in, in.root()["transfer"], "transfer", {}, 3.0, limits);
  };
  const ModbusOptions d = parse("transfer: {type: modbus, host: h}");
  EXPECT_EQ(*d.settle_tolerance, 0.05);  // [mm]
  EXPECT_EQ(*d.following_error, 0.2);
  const ModbusOptions wide = parse("transfer: {type: modbus, host: h, settle_tolerance: 0.1}");
  EXPECT_EQ(*wide.following_error, 0.4);
  SafetyLimits tight;
  tight.max_increment = 0.1e-3;  // [m]
  EXPECT_EQ(*parse("transfer: {type: modbus, host: h}", &tight).following_error, 0.1);
  // A window wider than an increment is not a settled move.
  try {
    parse("transfer: {type: modbus, host: h, settle_tolerance: 6}");
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("run.yaml:1: transfer.settle_tolerance: 6 mm is wider "
                                         "than the slot's safety.max_increment"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(parse("transfer: {type: modbus, host: h, settle_tolerance: 0}"), ConfigError);
}

TEST(SettledReading, AModbusControllerThatAcksBeforeItUpdatesItsDataIsStopped) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "stale@3"});
  ModbusTransfer transfer(modbus::Options(server));
  transfer.Activate();
  EXPECT_EQ(ExecuteOne(transfer, 1.0).position, 1.0);
  EXPECT_EQ(ExecuteOne(transfer, 1.5).position, 1.5);
  // Command 3 is acknowledged with command 2's position: 0.5 mm off, beyond the following
  // error too, but the stale rule names the cause.
  const SafetyStop stop = StopOf([&] { ExecuteOne(transfer, 2.0); });
  EXPECT_EQ(stop.limit(), "stale_acknowledgement");
  const std::string what = stop.what();
  EXPECT_NE(what.find("acknowledged command 2 mm (sequence"), std::string::npos) << what;
  EXPECT_NE(what.find("measured position 1.5 mm is the one of the previous command 1.5 mm"),
            std::string::npos) << what;
  EXPECT_NE(what.find("the hold coil was set"), std::string::npos) << what;
  EXPECT_NE(modbus::TransferFailure([&] { ExecuteOne(transfer, 2.0); }).find("not active"),
            std::string::npos);
}

TEST(SettledReading, AStaleAckWithinTheFollowingErrorIsStoppedToo) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "stale@2"});
  ModbusOptions o = modbus::Options(server);
  o.following_error = 2.0;  // [mm]: the old default; the stale rule does not depend on it
  ModbusTransfer transfer(o);
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  EXPECT_EQ(StopOf([&] { ExecuteOne(transfer, 1.3); }).limit(), "stale_acknowledgement");
}

TEST(SettledReading, A1point5MmOffsetOnActuator2OfTwoStopsNamingIt) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--actuators", "2", "--stiffness-matrix",
                                               "5,1.2;1.2,3", "--p0-mm", "20,30", "--fault",
                                               "offset@2/2", "--offset-mm", "1.5"});
  ModbusOptions o = modbus::Options(server);
  o.maps = {modbus::StridedMap(modbus::RegisterMap{}, {}, 0),
            modbus::StridedMap(modbus::RegisterMap{}, {}, 1)};
  ModbusTransfer transfer(o);
  EXPECT_EQ(*transfer.options().following_error, 0.2);  // the default: 4 × 0.05 mm
  transfer.Activate();
  std::array<Measurement, 2> out;
  transfer.Execute(std::array<double, 2>{20.5, 30.5}, out);  // both settled
  const SafetyStop stop =
      StopOf([&] { transfer.Execute(std::array<double, 2>{21.0, 31.0}, out); });
  EXPECT_EQ(stop.limit(), "following_error");
  EXPECT_NEAR(stop.value(), 1.5e-3, 1e-9);
  const std::string what = stop.what();
  EXPECT_NE(what.find("actuator 2 acknowledged command 31 mm"), std::string::npos) << what;
  EXPECT_NE(what.find("every actuator's hold coil was set"), std::string::npos) << what;
}

}  // namespace
}  // namespace hybridtest::transfer
