// ModbusTransfer::Probe (modbus_transfer.h): one look at the controller without moving.
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"

namespace hybridtest::transfer::modbus {

std::optional<ProbeReading> ModbusTransfer::Probe() {
  if (ctx_ == nullptr) Connect();
  const Readout r = ReadRegisters("the probe, before anything moves");
  const RegisterMap& m = options_.map;
  const StatusBits& b = m.status_bits;
  ProbeReading reading;
  reading.measurement = Measurement{r.position, r.force, 0.0};
  if (m.status) {
    reading.status = fmt::format("status 0x{:04x}: {}, {}, {}", r.status,
                                 Bit(r, b.fault) ? "FAULT" : "no fault",
                                 b.enabled < 0      ? "enable not reported"
                                 : Bit(r, b.enabled) ? "enabled"
                                                     : "not enabled",
                                 Bit(r, b.holding) ? "holding" : "not holding");
  } else {
    reading.status = "no status register in the map";
  }
  if (Bit(r, b.fault)) {
    reading.problem = fmt::format("the controller reports a fault (status bit {}): clear it at "
                                  "the controller first", b.fault);
  } else if (!std::isfinite(r.position) || !std::isfinite(r.force)) {
    reading.problem = fmt::format("position or force is not a number ({}): check the map's "
                                  "type, word_order and byte_order", Describe(r));
  }
  return reading;
}

}  // namespace hybridtest::transfer::modbus
