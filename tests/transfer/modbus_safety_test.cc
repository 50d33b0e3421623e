// ModbusTransfer's own checks against the pymodbus controller (tests/transfer/modbus_server.py)
// in a child process on 127.0.0.1: Read() (where the actuator is, without moving), the status
// bits on every exchange (holding, enabled) and the following-error limit. Skipped, with a
// message, when python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "hybridtest/transfer/safety.h"
#include "support/temp_dir.h"
#include "transfer/modbus_server_process.h"
#include "transfer/modbus_test_support.h"

namespace hybridtest::transfer::modbus {
namespace {

using testing::ModbusServerProcess;


std::filesystem::path LogFile(const std::string& name) {
  static const std::filesystem::path dir = test_support::FreshTempDir("modbus_safety");
  return dir / (name + ".log");
}

// Lines of the controller's --log-commands file (one per command received).
long CommandsReceived(const std::filesystem::path& log) {
  if (!std::filesystem::exists(log)) return 0;
  const std::string text = test_support::ReadText(log);
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

TEST(ModbusRead, ReportsWhereTheActuatorIsWithoutSendingACommand) {
  REQUIRE_PYMODBUS();
  const auto log = LogFile("read");
  // A controller restarted with the actuator at 7 mm, specimen unloaded at 5 mm.
  auto server = ModbusServerProcess::Pymodbus({"--start-mm", "7", "--p0-mm", "5", "--stiffness",
                                               "2", "--log-commands", log.string()});
  ModbusTransfer transfer(Options(server));
  EXPECT_FALSE(ReadOne(transfer).has_value()) << "not connected before Activate";
  transfer.Activate();
  const long before = transfer.requests();
  const auto read = ReadOne(transfer);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->position, 7.0);  // [mm], bench units
  EXPECT_EQ(read->force, 4.0);     // [N] = 2 N/mm × (7 − 5) mm
  EXPECT_EQ(transfer.requests() - before, 1) << "one read, no write";
  EXPECT_EQ(CommandsReceived(log), 0) << "Read() must not command anything";
  // Reading twice changes nothing; a move then shows in the next read.
  EXPECT_EQ(ReadOne(transfer)->position, 7.0);
  ExecuteOne(transfer, 7.5);
  EXPECT_EQ(ReadOne(transfer)->position, 7.5);
  EXPECT_EQ(CommandsReceived(log), 1);
}

TEST(ModbusRead, AFailedReadRefusesTheNextMoveUntilActivated) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  server.Kill();
  std::optional<Measurement> read;
  EXPECT_NO_THROW(read = ReadOne(transfer));
  EXPECT_FALSE(read.has_value());
  // Resume must not re-impose a command blind: the next move is refused, naming why.
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("command 1.5 mm not sent: the actuator's position could not be read"),
            std::string::npos) << error;
  EXPECT_NE(error.find("failed to read input registers 0–5"), std::string::npos) << error;
}

TEST(ModbusRead, GivesNothingWhileTheControllerHolds) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  transfer.Hold();  // the hold coil: the controller reports holding (status bit 2)
  EXPECT_FALSE(ReadOne(transfer).has_value());
  transfer.Activate();  // clears the hold coil and the refusal
  ASSERT_TRUE(ReadOne(transfer).has_value());
  EXPECT_EQ(ExecuteOne(transfer, 1.1).position, static_cast<float>(1.1));
}

TEST(ModbusStatus, HoldingBitMidRunStopsTheRunEvenIfTheCommandIsAcknowledged) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "holding@2"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("reports holding (status bit 2)"), std::string::npos) << error;
  EXPECT_NE(error.find("ack 2 (input register 4)"), std::string::npos) << "acked, still refused: "
                                                                       << error;
  EXPECT_NE(error.find("status 0x0005"), std::string::npos) << error;  // enabled | holding
  EXPECT_NO_THROW(transfer.Hold());
}

TEST(ModbusStatus, DroppedEnableMidRunStopsTheRun) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "disabled@2"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("dropped the enable (status bit 0)"), std::string::npos) << error;
  EXPECT_NE(error.find("status 0x0000"), std::string::npos) << error;
}

TEST(ModbusStatus, UncheckedBitsAreIgnored) {
  REQUIRE_PYMODBUS();
  // A map that leaves the holding bit unchecked (-1) accepts the same controller.
  auto server = ModbusServerProcess::Pymodbus({"--fault", "holding@2"});
  ModbusOptions o = Options(server);
  o.maps[0].status_bits.holding = -1;
  ModbusTransfer transfer(o);
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  EXPECT_EQ(ExecuteOne(transfer, 1.5).position, 1.5);
}

// The SafetyStop that `f` throws; fails the test if there is none.
template <class F>
SafetyStop ExpectSafetyStop(F&& f) {
  try {
    f();
  } catch (const SafetyStop& e) {
    return e;
  }
  ADD_FAILURE() << "no SafetyStop";
  return SafetyStop("none", 0, 0, 0, 0, {}, "");
}

TEST(ModbusFollowingError, AMeasuredPosition50MmOffTheCommandIsASafetyStop) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "offset@2", "--offset-mm", "50"});
  ModbusTransfer transfer(Options(server));
  EXPECT_EQ(*transfer.options().following_error, 0.2);  // default: 4 × 0.05 mm, the map's unit
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const SafetyStop stop = ExpectSafetyStop([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_EQ(stop.limit(), "following_error");
  EXPECT_NEAR(stop.value(), 0.050, 1e-12);       // [m]
  EXPECT_NEAR(stop.limit_value(), 0.0002, 1e-12);  // [m]
  const std::string what = stop.what();
  EXPECT_NE(what.find("command 1.5 mm"), std::string::npos) << what;
  EXPECT_NE(what.find("measured position 51.5 mm"), std::string::npos) << what;
  EXPECT_NE(what.find("> following_error 0.2 mm"), std::string::npos) << what;
  EXPECT_NE(what.find("the hold coil was set"), std::string::npos) << what;
  // Held: nothing more moves until the next Activate.
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 1.5); }).find("not active"), std::string::npos);
}

TEST(ModbusFollowingError, TheLimitIsConfigurable) {
  REQUIRE_PYMODBUS();
  // 4 mm off: within a configured 5 mm ...
  {
    auto server = ModbusServerProcess::Pymodbus({"--fault", "offset@2", "--offset-mm", "4"});
    ModbusOptions o = Options(server);
    o.following_error = 5.0;
    ModbusTransfer transfer(o);
    transfer.Activate();
    ExecuteOne(transfer, 1.0);
    EXPECT_EQ(ExecuteOne(transfer, 1.5).position, 5.5);
  }
  // ... beyond a configured 3 mm.
  auto server = ModbusServerProcess::Pymodbus({"--fault", "offset@2", "--offset-mm", "4"});
  ModbusOptions o = Options(server);
  o.following_error = 3.0;
  ModbusTransfer transfer(o);
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const SafetyStop stop = ExpectSafetyStop([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NEAR(stop.value(), 0.004, 1e-12);
  EXPECT_NEAR(stop.limit_value(), 0.003, 1e-12);
}

TEST(ModbusFollowingError, ConstructorRejectsANonPositiveLimit) {
  ModbusOptions o;
  o.following_error = 0.0;
  EXPECT_THROW(ModbusTransfer{o}, ConfigError);
  o.following_error = std::nan("");
  EXPECT_THROW(ModbusTransfer{o}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
