// ModbusTransfer with several actuators against the pymodbus controller serving them on one
// coupled specimen (tests/transfer/modbus_server.py --actuators 2): every command goes out
// before any ack is awaited, each actuator acknowledges its own sequence, and a problem on one
// actuator holds every one (the controller's holding bits follow its hold coils, read back by
// a second client). Skipped, with a message, when python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "transfer/modbus_server_process.h"
#include "transfer/modbus_test_support.h"

namespace hybridtest::transfer::modbus {
namespace {

using testing::ModbusServerProcess;

double Float32(double v) { return static_cast<float>(v); }

// K = [[5, 1.2], [1.2, 3]] N/mm, zero force at 20 and 30 mm.
std::vector<std::string> TwoActuators(std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"--actuators", "2", "--stiffness-matrix", "5,1.2;1.2,3",
                                "--p0-mm", "20,30"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// The default profile twice, packed (`map: {actuators: 2}`).
ModbusOptions Packed(const ModbusServerProcess& server) {
  ModbusOptions o = Options(server);
  o.maps = {StridedMap(RegisterMap{}, {}, 0), StridedMap(RegisterMap{}, {}, 1)};
  return o;
}

// The status each actuator reports now, read by a second client without moving anything.
std::string StatusSeenByAnotherClient(const ModbusServerProcess& server) {
  ModbusTransfer observer(Packed(server));
  return observer.Probe()->status;
}

TEST(ModbusTwoActuators, OneWriteAndOneReadCarryBothActuatorsThroughTheCoupledSpecimen) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(TwoActuators());
  ModbusTransfer transfer(Packed(server));
  EXPECT_EQ(transfer.num_actuators(), 2);
  transfer.Activate();
  const std::array<std::array<double, 2>, 3> commands = {{{21.0, 31.0}, {19.5, 30.25},
                                                          {20.123456789, 29.9}}};
  for (const auto& c : commands) {
    std::array<Measurement, 2> out;
    const long before = transfer.requests();
    transfer.Execute(c, out);
    EXPECT_EQ(transfer.requests() - before, 2) << "one write (holding 0–5), one read (input 0–11)";
    const double x1 = Float32(c[0]) - 20.0, x2 = Float32(c[1]) - 30.0;
    EXPECT_EQ(out[0].position, Float32(c[0]));
    EXPECT_EQ(out[1].position, Float32(c[1]));
    EXPECT_EQ(out[0].force, Float32(5.0 * x1 + 1.2 * x2));
    EXPECT_EQ(out[1].force, Float32(1.2 * x1 + 3.0 * x2));
    EXPECT_EQ(out[0].lab_time, out[1].lab_time);
  }
  const auto all = transfer.ReadAll();
  ASSERT_TRUE(all.has_value());
  EXPECT_EQ((*all)[1].position, Float32(29.9));
  // One command, or one reading, means nothing here: refused, nothing sent.
  EXPECT_FALSE(ReadOne(transfer).has_value());
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 20.0); }).find("one command for 2 actuators"),
            std::string::npos);
  std::vector<Measurement> one(1);
  EXPECT_NE(TransferFailure([&] { transfer.Execute(std::vector<double>{20.0}, one); })
                .find("1 commands for 2 actuators: nothing was sent"),
            std::string::npos);
  transfer.Deactivate();
}

TEST(ModbusTwoActuators, BlocksApartAreWrittenOneByOneBeforeAnyAckIsAwaited) {
  REQUIRE_PYMODBUS();
  // Actuator 2's block at holding 100, input 50, coils 10–11; float64 values.
  auto server = ModbusServerProcess::Pymodbus(TwoActuators(
      {"--type", "float64", "--holding-base", "0,100", "--input-base", "0,50", "--coil-base",
       "0,10", "--ack-delay-ms", "20"}));
  ModbusOptions o = Options(server);
  RegisterMap a;
  a.command.type = a.position.type = a.force.type = ValueType::kFloat64;
  a.sequence.address = 4;
  a.force.address = 4;
  a.ack.address = 8;
  a.status->address = 9;
  RegisterMap b = a;
  for (RegisterField* f : {&b.command, &b.sequence}) f->address += 100;
  for (RegisterField* f : {&b.position, &b.force, &b.ack, &*b.status}) f->address += 50;
  b.enable_coil = 10;
  b.hold_coil = 11;
  o.maps = {a, b};
  o.poll_interval = 0.002;
  ModbusTransfer transfer(o);
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{20.1234567890123, 30.9876543210987};
  const long before = transfer.requests();
  transfer.Execute(c, out);
  // Two writes, then reads (input 0–59 in one request) until both acks are in (20 ms later).
  EXPECT_GT(transfer.requests() - before, 3);
  EXPECT_EQ(out[0].position, c[0]);  // float64 on the wire: exact
  EXPECT_EQ(out[1].position, c[1]);
  const double x1 = c[0] - 20.0, x2 = c[1] - 30.0;
  EXPECT_DOUBLE_EQ(out[0].force, 5.0 * x1 + 1.2 * x2);
  EXPECT_DOUBLE_EQ(out[1].force, 1.2 * x1 + 3.0 * x2);
}

TEST(ModbusTwoActuators, ACommandOneActuatorsTypeCannotHoldSendsNone) {
  REQUIRE_PYMODBUS();
  const std::string log = ::testing::TempDir() + "modbus_multi_none_sent.log";
  std::remove(log.c_str());
  auto server = ModbusServerProcess::Pymodbus(TwoActuators({"--log-commands", log}));
  ModbusOptions o = Packed(server);
  // Actuator 2's command in counts of 0.01 mm (int16): 400 mm does not fit. Its block lies
  // apart from actuator 1's, so that the two are two writes.
  o.maps[1].command = {Table::kHolding, 10, ValueType::kInt16, 0.01};
  o.maps[1].sequence.address = 11;
  ModbusTransfer transfer(o);
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{20.5, 400.0};
  EXPECT_THROW(transfer.Execute(c, out), TransferError);
  std::ifstream in(log);
  std::string line;
  EXPECT_FALSE(std::getline(in, line)) << "a command was sent: " << line;
}

TEST(ModbusTwoActuators, PollsUntilBothLaggedActuatorsAcknowledge) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(TwoActuators(
      {"--actuator", "lag", "--settle-mm", "0.001", "--ack-delay-ms", "30"}));
  ModbusOptions o = Packed(server);
  o.poll_interval = 0.002;
  ModbusTransfer transfer(o);
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{22.0, 27.0};
  const long before = transfer.requests();
  transfer.Execute(c, out);
  EXPECT_GT(transfer.requests() - before, 3) << "the acks were not awaited";
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NEAR(out[k].position, c[k], 0.001) << k;  // settled within the tolerance
    EXPECT_NE(out[k].position, Float32(c[k])) << k;   // ... but not at the command: a real lag
  }
  const double x1 = out[0].position - 20.0, x2 = out[1].position - 30.0;
  EXPECT_NEAR(out[0].force, 5.0 * x1 + 1.2 * x2, 1e-5);
  EXPECT_NEAR(out[1].force, 1.2 * x1 + 3.0 * x2, 1e-5);
}

TEST(ModbusTwoActuators, AFaultOnActuator2HoldsBothAndNamesIt) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(TwoActuators({"--fault", "fault@2/2"}));
  ModbusTransfer transfer(Packed(server));
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> first{20.5, 30.5}, second{21.0, 31.0};
  transfer.Execute(first, out);
  const std::string error = TransferFailure([&] { transfer.Execute(second, out); });
  EXPECT_NE(error.find("actuator 2 reports a fault (status bit 1)"), std::string::npos) << error;
  EXPECT_NE(error.find("every actuator's hold coil was set"), std::string::npos) << error;
  EXPECT_NE(error.find("input register 11"), std::string::npos) << error;  // its status register
  // Both hold coils are set in the controller: each actuator reports holding.
  const std::string status = StatusSeenByAnotherClient(server);
  EXPECT_NE(status.find("actuator 1: position 21 mm"), std::string::npos) << status;
  EXPECT_NE(status.find("status 0x0005: no fault, enabled, holding; actuator 2"),
            std::string::npos) << status;
  EXPECT_NE(status.find("actuator 2: position 30.5 mm"), std::string::npos) << status;
  EXPECT_NE(status.find("status 0x0007: FAULT, enabled, holding"), std::string::npos) << status;
  EXPECT_NE(TransferFailure([&] { transfer.Execute(second, out); }).find("not active"),
            std::string::npos);
  // The next start refuses while actuator 2 shows the fault; the probe names it.
  EXPECT_NE(TransferFailure([&] { transfer.Activate(); }).find("actuator 2 reports a fault"),
            std::string::npos);
  ModbusTransfer observer(Packed(server));
  EXPECT_NE(observer.Probe()->problem.find("actuator 2: the controller reports a fault"),
            std::string::npos);
}

TEST(ModbusTwoActuators, AMissingAckOnOneActuatorTimesOutNamingItAndHoldsBoth) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(TwoActuators({"--fault", "silent@1/2"}));
  ModbusTransfer transfer(Packed(server));
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{20.5, 30.5};
  const std::string error = TransferFailure([&] { transfer.Execute(c, out); });
  EXPECT_NE(error.find("actuator 2 did not acknowledge within 0.5 s"), std::string::npos) << error;
  EXPECT_NE(error.find("sequences [1, 1]"), std::string::npos) << error;
  EXPECT_NE(error.find("every actuator's hold coil was set"), std::string::npos) << error;
  const std::string status = StatusSeenByAnotherClient(server);
  EXPECT_NE(status.find("actuator 1: position 20.5 mm"), std::string::npos) << status;
  EXPECT_EQ(status.find("not holding"), std::string::npos) << "both hold: " << status;
}

TEST(ModbusTwoActuators, EachActuatorHasItsOwnFollowingErrorAndATripHoldsBoth) {
  REQUIRE_PYMODBUS();
  // From its first command, actuator 2 measures 3 mm off where it is: within actuator 1's
  // 5 mm, beyond actuator 2's 2 mm.
  auto server = ModbusServerProcess::Pymodbus(
      TwoActuators({"--fault", "offset@1/2", "--offset-mm", "3"}));
  ModbusOptions o = Packed(server);
  o.following_errors = {5.0, 2.0};
  o.position_tolerance = 10.0;  // let the first exchange through to the following error
  ModbusTransfer transfer(o);
  transfer.Activate();
  std::array<Measurement, 2> out;
  const std::array<double, 2> c{20.5, 30.5};
  try {
    transfer.Execute(c, out);
    ADD_FAILURE() << "no safety stop";
  } catch (const SafetyStop& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("actuator 2 acknowledged command 30.5 mm"), std::string::npos) << what;
    EXPECT_NE(what.find("measured position 33.5 mm"), std::string::npos) << what;
    EXPECT_NE(what.find("> following_error 2 mm"), std::string::npos) << what;
    EXPECT_NE(what.find("every actuator's hold coil was set"), std::string::npos) << what;
  }
  const std::string status = StatusSeenByAnotherClient(server);
  EXPECT_EQ(status.find("not holding"), std::string::npos) << "both hold: " << status;
}

TEST(ModbusTwoActuators, HoldSetsEveryHoldCoilAndActivateReleasesThem) {
  REQUIRE_PYMODBUS();
  auto server = ModbusServerProcess::Pymodbus(TwoActuators());
  ModbusTransfer transfer(Packed(server));
  transfer.Activate();
  transfer.Hold();
  std::string status = StatusSeenByAnotherClient(server);
  EXPECT_EQ(status.find("not holding"), std::string::npos) << status;
  transfer.Activate();
  status = StatusSeenByAnotherClient(server);
  EXPECT_NE(status.find("actuator 2: position 30 mm, force 0 N, status 0x0001: no fault, enabled, "
                        "not holding"), std::string::npos) << status;
  // A shared hold coil (stride coils 0) is written once.
  auto shared = ModbusServerProcess::Pymodbus(TwoActuators({"--stride-coils", "0"}));
  ModbusOptions o = Options(shared);
  Stride stride;
  stride.coils = 0;
  o.maps = {StridedMap(RegisterMap{}, stride, 0), StridedMap(RegisterMap{}, stride, 1)};
  ModbusTransfer one_coil(o);
  one_coil.Activate();
  const long before = one_coil.requests();
  one_coil.Hold();
  EXPECT_EQ(one_coil.requests() - before, 1);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
