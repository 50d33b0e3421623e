#pragma once
// Shared by the Modbus transfer tests (modbus_transfer_test.cc, modbus_safety_test.cc): the
// options for a test controller on 127.0.0.1, the message of a TransferError, and the skip
// when python3-pymodbus is not installed.
#include <gtest/gtest.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "transfer/modbus_server_process.h"

#define REQUIRE_PYMODBUS()                                                                     \
  if (!::hybridtest::testing::PymodbusAvailable())                                            \
  GTEST_SKIP() << ::hybridtest::testing::kPymodbusMissing

namespace hybridtest::transfer::modbus {

// Short timeouts: the controller answers on loopback or not at all.
inline ModbusOptions Options(const testing::ModbusServerProcess& server) {
  ModbusOptions o;
  o.port = server.port();
  o.ack_timeout = 0.5;
  o.response_timeout = 0.5;
  o.connect_timeout = 2.0;
  return o;
}

// The message of the TransferError that `f` throws ("" if none).
template <class F>
std::string TransferFailure(F&& f) {
  try {
    f();
  } catch (const TransferError& e) {
    return e.what();
  }
  return "";
}

}  // namespace hybridtest::transfer::modbus
