#pragma once
// Helpers of ModbusTransfer's files (modbus_transfer.cc, modbus_link.cc, modbus_execute.cc):
// libmodbus's error codes in words.
#include <string>

namespace hybridtest::transfer::modbus {

// "Modbus exception 4 (Slave device or server failure)" or libmodbus's text for `error`.
std::string ModbusErrorText(int error);
// True if `error` (an errno from libmodbus) is a Modbus exception answered by the controller.
bool IsModbusException(int error);

}  // namespace hybridtest::transfer::modbus
