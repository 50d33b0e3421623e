// ModbusTransfer against a real peer: the pymodbus controller tests/transfer/modbus_server.py
// (a Modbus stack we did not write) in a child process on 127.0.0.1. Skipped, with a message,
// when python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "transfer/modbus_server_process.h"
#include "transfer/modbus_test_support.h"

namespace hybridtest::transfer::modbus {
namespace {

using testing::ModbusServerProcess;


double Float32(double v) { return static_cast<float>(v); }

TEST(ModbusTransfer, IdealControllerReproducesTheSpecimenLaw) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--stiffness", "5.25", "--p0-mm", "20"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  double last_lab_time = -1.0;
  for (double command : {20.0, 21.5, 19.25, 20.123456789}) {
    const Measurement m = ExecuteOne(transfer, command);
    EXPECT_EQ(m.position, Float32(command));  // the command went through float32 once
    EXPECT_EQ(m.force, Float32(5.25 * (Float32(command) - 20.0)));
    EXPECT_GT(m.lab_time, last_lab_time);  // wall time since Activate
    last_lab_time = m.lab_time;
  }
  // One write and one read per command when the ack is immediate.
  const long before = transfer.requests();
  ExecuteOne(transfer, 20.5);
  EXPECT_EQ(transfer.requests() - before, 2);
  EXPECT_EQ(transfer.bench_units().length_name, "mm");
  transfer.Deactivate();
  EXPECT_FALSE(transfer.is_connected());
}

TEST(ModbusTransfer, PollsUntilALaggedControllerAcknowledges) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(
      {"--actuator", "lag", "--settle-mm", "0.001", "--ack-delay-ms", "30"});
  ModbusOptions o = Options(server);
  o.poll_interval = 0.002;
  ModbusTransfer transfer(o);
  transfer.Activate();
  const long before = transfer.requests();
  const Measurement m = ExecuteOne(transfer, 2.0);
  EXPECT_GT(transfer.requests() - before, 3) << "the ack was not awaited";
  EXPECT_NEAR(m.position, 2.0, 0.001);     // settled within the controller's tolerance
  EXPECT_NE(m.position, Float32(2.0));     // ... but not at the command: a real lag
  EXPECT_NEAR(m.force, 5.25 * m.position, 1e-5);
}

TEST(ModbusTransfer, LabTimeComesFromTheBenchClockRegisterWhenMapped) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--lab-time", "--overhead-ms", "1130"});
  ModbusOptions o = Options(server);
  o.maps[0].lab_time = RegisterField{Table::kInput, 6, ValueType::kUint32, 0.001};
  ModbusTransfer transfer(o);
  transfer.Activate();
  EXPECT_DOUBLE_EQ(ExecuteOne(transfer, 0.1).lab_time, 1.13);
  EXPECT_DOUBLE_EQ(ExecuteOne(transfer, 0.2).lab_time, 2.26);
}

TEST(ModbusTransfer, SilentControllerTimesOutNamingTheAckRegister) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "silent@2"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const auto start = std::chrono::steady_clock::now();
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(error.find("did not acknowledge within 0.5 s"), std::string::npos) << error;
  EXPECT_NE(error.find("127.0.0.1:" + std::to_string(server.port())), std::string::npos) << error;
  EXPECT_NE(error.find("ack 1 (input register 4)"), std::string::npos) << error;
  EXPECT_NE(error.find("sequence 2"), std::string::npos) << error;
  EXPECT_LT(waited, 5.0);  // bounded (not a timing assertion: a hang would be minutes)
  EXPECT_NE(error.find("the hold coil was set"), std::string::npos) << error;
  EXPECT_TRUE(transfer.is_connected()) << "the link works: it stays open for the hold";
  EXPECT_NO_THROW(transfer.Hold());
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 1.5); }).find("not active"), std::string::npos);
}

TEST(ModbusTransfer, FaultBitStopsTheTestAndHoldStillReachesTheController) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "fault@3"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  ExecuteOne(transfer, 1.1);
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.2); });
  EXPECT_NE(error.find("reports a fault (status bit 1)"), std::string::npos) << error;
  EXPECT_NE(error.find("status 0x0003"), std::string::npos) << error;  // enabled | fault
  EXPECT_TRUE(transfer.is_connected());
  EXPECT_NO_THROW(transfer.Hold());
  EXPECT_TRUE(transfer.is_connected()) << "the hold coil write should have been answered";
  // A controller in fault refuses to start again.
  EXPECT_NE(TransferFailure([&] { transfer.Activate(); }).find("fault"), std::string::npos);
}

TEST(ModbusTransfer, ModbusExceptionIsATransferError) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "exception@2"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("Modbus exception 4"), std::string::npos) << error;
  EXPECT_NE(error.find("holding registers 0–2"), std::string::npos) << error;
  EXPECT_NO_THROW(transfer.Hold());
}

TEST(ModbusTransfer, KilledControllerIsATransferErrorAndHoldDoesNotThrow) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  server.Kill();
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("connection was closed"), std::string::npos) << error;
  EXPECT_FALSE(transfer.is_connected());
  EXPECT_NO_THROW(transfer.Hold());
  EXPECT_NE(TransferFailure([&] { transfer.Activate(); }).find("cannot connect"),
            std::string::npos);
}

TEST(ModbusTransfer, MuteControllerHitsTheResponseTimeout) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--fault", "mute@2"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
  EXPECT_NE(error.find("timed out"), std::string::npos) << error;
  EXPECT_NO_THROW(transfer.Hold());
}

TEST(ModbusTransfer, WrongWordOrderFailsTheFirstExchangesPlausibilityCheck) {
  REQUIRE_PYMODBUS();
  // A real (lagged) actuator at 20 mm: its settled position is not bit-equal to the command,
  // so reading it word-swapped gives an absurd number.
  auto server = ModbusServerProcess::Pymodbus(
      {"--start-mm", "20", "--p0-mm", "20", "--actuator", "lag", "--stiffness", "7.2"});
  ModbusOptions o = Options(server);
  o.maps[0].word_order = WordOrder::kLowFirst;
  ModbusTransfer transfer(o);
  transfer.Activate();
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 20.0); });
  EXPECT_NE(error.find("implausible first measurement"), std::string::npos) << error;
  EXPECT_NE(error.find("word_order"), std::string::npos) << error;
}

TEST(ModbusTransfer, WrongUnitIdIsRefusedAtActivate) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({"--unit", "1"});
  ModbusOptions o = Options(server);
  o.unit_id = 7;
  ModbusTransfer transfer(o);
  const std::string error = TransferFailure([&] { transfer.Activate(); });
  EXPECT_NE(error.find("unit 7"), std::string::npos) << error;
  // pymodbus ignores requests for other units, as many devices do: the request times out.
  EXPECT_NE(error.find("timed out"), std::string::npos) << error;
  EXPECT_NE(error.find("check unit_id"), std::string::npos) << error;
}

TEST(ModbusTransfer, ExecuteRefusesUntilActivatedAndResumesAfterHold) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus({});
  ModbusTransfer transfer(Options(server));
  EXPECT_NO_THROW(transfer.Hold());  // any state
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 1.0); }).find("not active"), std::string::npos);
  transfer.Activate();
  ExecuteOne(transfer, 1.0);
  transfer.Hold();  // the controller now refuses commands until the hold coil is cleared
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 1.1); }).find("not active"), std::string::npos);
  transfer.Activate();  // clears the hold coil
  EXPECT_EQ(ExecuteOne(transfer, 1.1).position, Float32(1.1));
}

TEST(ModbusTransfer, ConstructorRejectsBadOptions) {
  ModbusOptions o;
  o.ack_timeout = 0.0;
  EXPECT_THROW(ModbusTransfer{o}, ConfigError);
  o = ModbusOptions{};
  o.unit_id = 300;
  EXPECT_THROW(ModbusTransfer{o}, ConfigError);
  o = ModbusOptions{};
  o.maps[0].sequence.address = 7;  // not next to the command
  EXPECT_THROW(ModbusTransfer{o}, ConfigError);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
