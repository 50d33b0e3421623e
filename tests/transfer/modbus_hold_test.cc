// A Modbus controller with one actuator holds on every failure of a move, as the ADS PLC
// always did (the acknowledged move, transfer/acknowledged_move.h): a fault, a dropped enable,
// a refused write and an implausible first measurement set the hold coil, and the transfer
// refuses the next command until it is activated again. Against the pymodbus controller
// (tests/transfer/modbus_server.py) on 127.0.0.1; skipped, with a message, when
// python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "support/temp_dir.h"
#include "transfer/modbus_server_process.h"
#include "transfer/modbus_test_support.h"

namespace hybridtest::transfer::modbus {
namespace {

using testing::ModbusServerProcess;

// What a second client sees of the controller: "…, status 0x0005: no fault, enabled, holding".
std::string StatusSeenByAnObserver(const ModbusServerProcess& server) {
  ModbusTransfer observer(Options(server));
  return observer.Probe()->status;
}

long Lines(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) return 0;
  const std::string text = test_support::ReadText(file);
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

struct Case {
  std::vector<std::string> args;  // of the controller
  std::string message;            // in the TransferError of command 2
};

TEST(ModbusHold, OneActuatorHoldsOnEveryFailureAndRefusesTheNextCommand) {
  REQUIRE_PYMODBUS();
  const auto dir = test_support::FreshTempDir("modbus_hold");
  const Case cases[] = {
      {{"--fault", "fault@2"}, "reports a fault (status bit 1)"},
      {{"--fault", "disabled@2"}, "dropped the enable (status bit 0)"},
      {{"--fault", "exception@2"}, "Modbus exception 4"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const auto log = dir / ("commands" + std::to_string(++i) + ".log");
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--log-commands", log.string()});
    auto server = ModbusServerProcess::Pymodbus(args);
    ModbusTransfer transfer(Options(server));
    transfer.Activate();
    ExecuteOne(transfer, 1.0);
    const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
    EXPECT_NE(error.find(c.message), std::string::npos) << error;
    const std::string status = StatusSeenByAnObserver(server);
    EXPECT_NE(status.find(", holding"), std::string::npos) << c.message << ": " << status;
    // Nothing more is sent until the next Activate.
    const std::string refused = TransferFailure([&] { ExecuteOne(transfer, 1.5); });
    EXPECT_NE(refused.find("not active"), std::string::npos) << c.message << ": " << refused;
    EXPECT_EQ(Lines(log), 2) << c.message << ": a command was sent after the failure";
  }
}

TEST(ModbusHold, AnImplausibleFirstMeasurementHoldsTheController) {
  REQUIRE_PYMODBUS();
  // 5 mm between where the actuator is and what it reports: beyond the 1 mm of the first
  // exchange's plausibility (a position sensor's offset, a wrong scale).
  auto server = ModbusServerProcess::Pymodbus({"--fault", "offset@1", "--offset-mm", "5"});
  ModbusTransfer transfer(Options(server));
  transfer.Activate();
  const std::string error = TransferFailure([&] { ExecuteOne(transfer, 1.0); });
  EXPECT_NE(error.find("implausible first measurement"), std::string::npos) << error;
  EXPECT_NE(error.find("the hold coil was set"), std::string::npos) << error;
  const std::string status = StatusSeenByAnObserver(server);
  EXPECT_NE(status.find(", holding"), std::string::npos) << status;
  EXPECT_NE(TransferFailure([&] { ExecuteOne(transfer, 1.0); }).find("not active"),
            std::string::npos);
}

}  // namespace
}  // namespace hybridtest::transfer::modbus
