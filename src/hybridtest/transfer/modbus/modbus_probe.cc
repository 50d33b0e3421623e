// ModbusTransfer::Probe (modbus_transfer.h): one look at the controller without moving.
#include <fmt/core.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"

namespace hybridtest::transfer::modbus {

std::optional<ProbeReading> ModbusTransfer::Probe() {
  if (ctx_ == nullptr) Connect();
  const std::vector<Readout> r = ReadRegisters("the probe, before anything moves");
  const bool several = maps_.size() > 1;
  ProbeReading reading;
  for (std::size_t k = 0; k < maps_.size(); ++k) {
    reading.measurements.push_back(Measurement{r[k].position, r[k].force, 0.0});
    const RegisterMap& m = maps_[k];
    const StatusBits& b = m.status_bits;
    const std::string who = several ? fmt::format("actuator {}: ", k + 1) : "";
    std::string status;
    if (m.status) {
      status = fmt::format("status 0x{:04x}: {}, {}, {}", r[k].status,
                           Bit(r[k], b.fault) ? "FAULT" : "no fault",
                           b.enabled < 0          ? "enable not reported"
                           : Bit(r[k], b.enabled) ? "enabled"
                                                  : "not enabled",
                           Bit(r[k], b.holding) ? "holding" : "not holding");
    } else {
      status = "no status register in the map";
    }
    if (several) {
      status = fmt::format("{}position {} {}, force {} {}, {}", who, r[k].position,
                           m.units.length_name, r[k].force, m.units.force_name, status);
    }
    reading.status += (k == 0 ? "" : "; ") + status;
    if (!reading.problem.empty()) continue;
    if (Bit(r[k], b.fault)) {
      reading.problem = fmt::format("{}the controller reports a fault (status bit {}): clear it "
                                    "at the controller first", who, b.fault);
    } else if (!std::isfinite(r[k].position) || !std::isfinite(r[k].force)) {
      reading.problem = fmt::format("{}position or force is not a number ({}): check the map's "
                                    "type, word_order and byte_order", who, Describe(r[k], k));
    }
  }
  return reading;
}

}  // namespace hybridtest::transfer::modbus
