// ModbusTransfer (modbus_transfer.h): the connection and its requests — connect, close, the
// failure of a request, a coil write and the reads of the readout registers.
#include <errno.h>
#include <fmt/core.h>
#include <modbus.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_link.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"

namespace hybridtest::transfer::modbus {

std::string ModbusErrorText(int error) {
  if (IsModbusException(error)) {
    return fmt::format("Modbus exception {} ({})", error - MODBUS_ENOBASE, modbus_strerror(error));
  }
  return modbus_strerror(error);
}

bool IsModbusException(int error) { return error >= EMBXILFUN && error <= EMBXGTAR; }

std::string ModbusTransfer::Endpoint() const {
  const bool v6 = options_.host.find(':') != std::string::npos;
  return v6 ? fmt::format("[{}]:{} unit {}", options_.host, options_.port, options_.unit_id)
            : fmt::format("{}:{} unit {}", options_.host, options_.port, options_.unit_id);
}

std::string ModbusTransfer::Subject(std::size_t k) const {
  if (maps_.size() == 1) return fmt::format("the Modbus controller at {}", Endpoint());
  return fmt::format("the Modbus controller at {}: actuator {}", Endpoint(), k + 1);
}

void ModbusTransfer::SetResponseTimeout(double seconds) noexcept {
  if (ctx_ == nullptr) return;
  const auto micros = static_cast<std::uint64_t>(std::ceil(seconds * 1e6));
  modbus_set_response_timeout(ctx_, static_cast<std::uint32_t>(micros / 1000000),
                              static_cast<std::uint32_t>(micros % 1000000));
}

void ModbusTransfer::Close() noexcept {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
  active_ = false;
}

void ModbusTransfer::Fail(const std::string& message, bool close) {
  if (close) Close();
  throw TransferError(message);
}

void ModbusTransfer::FailRequest(const std::string& what) { FailRequest(what, errno); }

void ModbusTransfer::FailRequest(const std::string& what, int error) {
  const bool exception = IsModbusException(error);
  const std::string hint =
      error == ETIMEDOUT
          ? fmt::format(" (no answer within {} s; a controller ignores requests for another unit: "
                        "check unit_id {})", options_.response_timeout, options_.unit_id)
          : "";
  Fail(fmt::format("the Modbus controller at {} failed {}: {}{}{}", Endpoint(), what,
                   ModbusErrorText(error), hint,
                   exception ? "" : "; the connection was closed so the controller holds"),
       !exception);
}

void ModbusTransfer::Connect() {
  Close();
  const std::string service = std::to_string(options_.port);
  ctx_ = modbus_new_tcp_pi(options_.host.c_str(), service.c_str());
  if (ctx_ == nullptr) {
    throw TransferError(fmt::format("cannot create a Modbus/TCP context for {}: {}", Endpoint(),
                                    modbus_strerror(errno)));
  }
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);  // fail fast, never retry a move
  if (modbus_set_slave(ctx_, options_.unit_id) != 0) {
    Fail(fmt::format("unit_id {} refused by libmodbus: {}", options_.unit_id,
                     modbus_strerror(errno)), true);
  }
  SetResponseTimeout(options_.connect_timeout);  // libmodbus bounds connect() by it
  if (modbus_connect(ctx_) != 0) {
    const int error = errno;
    Close();
    throw TransferError(fmt::format(
        "cannot connect to the Modbus controller at {} within {} s: {}; check that it runs, "
        "the address (--bench HOST:PORT or transfer.host/port) and any firewall",
        Endpoint(), options_.connect_timeout, modbus_strerror(error)));
  }
  SetResponseTimeout(options_.response_timeout);
}

void ModbusTransfer::WriteCoil(int address, bool value, const std::string& why) {
  ++requests_;
  if (modbus_write_bit(ctx_, address, value ? 1 : 0) != 1) {
    FailRequest(fmt::format("to {} coil {} ({})", value ? "set" : "clear", address, why));
  }
}

int ModbusTransfer::ReadBlocks(std::vector<Readout>& r, std::string& failed) {
  if (ctx_ == nullptr) {
    failed = "the readout registers (not connected)";
    return ENOTCONN;
  }
  for (const RegisterBlock& b : reads_) {
    ++requests_;
    const bool is_input = b.table == Table::kInput;
    std::uint16_t* dest = (is_input ? input_ : holding_).data() + b.start;
    const int got = is_input ? modbus_read_input_registers(ctx_, b.start, b.count, dest)
                             : modbus_read_registers(ctx_, b.start, b.count, dest);
    if (got != b.count) {
      const int error = errno != 0 ? errno : EIO;
      failed = fmt::format("to read {} registers {}–{}", is_input ? "input" : "holding", b.start,
                           b.start + b.count - 1);
      return error;
    }
  }
  const auto at = [&](const RegisterField& f) {
    return (f.table == Table::kInput ? input_ : holding_).data() + f.address;
  };
  r.resize(maps_.size());
  const RegisterMap& first = maps_.front();
  const double lab_time = first.lab_time ? DecodeValue(first, *first.lab_time, at(*first.lab_time))
                                         : 0.0;
  for (std::size_t k = 0; k < maps_.size(); ++k) {
    const RegisterMap& m = maps_[k];
    r[k].position = DecodeValue(m, m.position, at(m.position));
    r[k].force = DecodeValue(m, m.force, at(m.force));
    r[k].ack = static_cast<std::uint64_t>(DecodeValue(m, m.ack, at(m.ack)));
    r[k].status = m.status ? static_cast<int>(DecodeValue(m, *m.status, at(*m.status))) : -1;
    r[k].lab_time = lab_time;
  }
  return 0;
}

std::vector<ModbusTransfer::Readout> ModbusTransfer::ReadRegisters(const std::string& why) {
  std::vector<Readout> r;
  std::string failed;
  if (const int error = ReadBlocks(r, failed); error != 0) {
    FailRequest(fmt::format("{} ({})", failed, why), error);
  }
  return r;
}

}  // namespace hybridtest::transfer::modbus
