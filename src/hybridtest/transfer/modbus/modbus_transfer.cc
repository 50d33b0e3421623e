// See modbus_transfer.h.
#include "hybridtest/transfer/modbus/modbus_transfer.h"

#include <errno.h>
#include <fmt/core.h>
#include <modbus.h>

#include <array>
#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::modbus {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

std::string ModbusErrorText(int error) {
  if (error >= EMBXILFUN && error <= EMBXGTAR) {
    return fmt::format("Modbus exception {} ({})", error - MODBUS_ENOBASE, modbus_strerror(error));
  }
  return modbus_strerror(error);
}

bool IsModbusException(int error) { return error >= EMBXILFUN && error <= EMBXGTAR; }

}  // namespace

ModbusTransfer::ModbusTransfer(ModbusOptions options) : options_(std::move(options)) {
  const ModbusOptions& o = options_;
  for (const auto& [name, value] :
       {std::pair{"connect_timeout", o.connect_timeout}, {"response_timeout", o.response_timeout},
        {"ack_timeout", o.ack_timeout}, {"hold_timeout", o.hold_timeout}}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw ConfigError(fmt::format("modbus transfer: {} = {} s: expected a positive time", name,
                                    value));
    }
  }
  if (!options_.position_tolerance) {
    options_.position_tolerance = 1e-3 / o.map.units.metres_per_length_unit;  // 1 mm
  }
  if (!options_.force_plausible) {
    options_.force_plausible = 1e6 / o.map.units.newtons_per_force_unit;  // 1 MN
  }
  if (!options_.following_error) {
    options_.following_error = SafetyLimits{}.max_increment / o.map.units.metres_per_length_unit;
  }
  if (!(o.poll_interval >= 0.0) || !(*o.position_tolerance > 0.0) || !(*o.force_plausible > 0.0)) {
    throw ConfigError(fmt::format(
        "modbus transfer: poll_interval = {} s, position_tolerance = {}, force_plausible = {}: "
        "expected a non-negative interval and positive plausibility bounds",
        o.poll_interval, *o.position_tolerance, *o.force_plausible));
  }
  if (!(*o.following_error > 0.0) || !std::isfinite(*o.following_error)) {
    throw ConfigError(fmt::format("modbus transfer: following_error = {} {}: expected a positive "
                                  "distance in the map's length unit",
                                  *o.following_error, o.map.units.length_name));
  }
  if (o.unit_id < 0 || o.unit_id > 255) {
    throw ConfigError(fmt::format("modbus transfer: unit_id = {}: expected 0..255 (usually 1; "
                                  "255 addresses a Modbus/TCP device directly)", o.unit_id));
  }
  ValidateRegisterMap(o.map, "modbus transfer: map");
}

ModbusTransfer::~ModbusTransfer() { Close(); }

std::string ModbusTransfer::Endpoint() const {
  const bool v6 = options_.host.find(':') != std::string::npos;
  return v6 ? fmt::format("[{}]:{} unit {}", options_.host, options_.port, options_.unit_id)
            : fmt::format("{}:{} unit {}", options_.host, options_.port, options_.unit_id);
}

std::string ModbusTransfer::Describe() const {
  const RegisterMap& m = options_.map;
  return fmt::format("Modbus/TCP controller at {} ({}, {}; command at {}, ack at {})",
                     Endpoint(), m.units.length_name, m.units.force_name,
                     DescribeField(m.command), DescribeField(m.ack));
}

std::string ModbusTransfer::Describe(const Readout& r) const {
  std::string text = fmt::format("ack {} ({}), position {} {} ({}), force {} {} ({})", r.ack,
                                 DescribeField(options_.map.ack), r.position,
                                 options_.map.units.length_name,
                                 DescribeField(options_.map.position), r.force,
                                 options_.map.units.force_name, DescribeField(options_.map.force));
  if (r.status >= 0) {
    text += fmt::format(", status 0x{:04x} ({})", r.status, DescribeField(*options_.map.status));
  }
  return text;
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

int ModbusTransfer::ReadBlocks(Readout& r, std::string& failed) const {
  const RegisterMap& m = options_.map;
  if (ctx_ == nullptr) {
    failed = "the readout registers (not connected)";
    return ENOTCONN;
  }
  // Registers by table, indexed from each block's start (a block is at most 125 registers).
  std::array<std::uint16_t, 128> input{}, holding{};
  int input_start = 0, holding_start = 0;
  for (const RegisterBlock& b : ReadoutBlocks(m)) {
    ++requests_;
    const bool is_input = b.table == Table::kInput;
    std::uint16_t* dest = is_input ? input.data() : holding.data();
    const int got = is_input ? modbus_read_input_registers(ctx_, b.start, b.count, dest)
                             : modbus_read_registers(ctx_, b.start, b.count, dest);
    if (got != b.count) {
      const int error = errno != 0 ? errno : EIO;
      failed = fmt::format("to read {} registers {}–{}", is_input ? "input" : "holding", b.start,
                           b.start + b.count - 1);
      return error;
    }
    (is_input ? input_start : holding_start) = b.start;
  }
  const auto at = [&](const RegisterField& f) {
    return f.table == Table::kInput ? input.data() + (f.address - input_start)
                                    : holding.data() + (f.address - holding_start);
  };
  r.position = DecodeValue(m, m.position, at(m.position));
  r.force = DecodeValue(m, m.force, at(m.force));
  r.ack = static_cast<std::uint64_t>(DecodeValue(m, m.ack, at(m.ack)));
  if (m.status) r.status = static_cast<int>(DecodeValue(m, *m.status, at(*m.status)));
  if (m.lab_time) r.lab_time = DecodeValue(m, *m.lab_time, at(*m.lab_time));
  return 0;
}

ModbusTransfer::Readout ModbusTransfer::ReadRegisters(const std::string& why) {
  Readout r;
  std::string failed;
  if (const int error = ReadBlocks(r, failed); error != 0) {
    FailRequest(fmt::format("{} ({})", failed, why), error);
  }
  return r;
}

std::string ModbusTransfer::StatusProblem(const Readout& r) const {
  const StatusBits& b = options_.map.status_bits;
  if (!options_.map.status) return "";
  if (Bit(r, b.fault)) return fmt::format("reports a fault (status bit {})", b.fault);
  if (b.enabled >= 0 && !Bit(r, b.enabled)) {
    return fmt::format("does not report the drive enabled (status bit {})", b.enabled);
  }
  if (Bit(r, b.holding)) return fmt::format("reports holding (status bit {})", b.holding);
  return "";
}

std::optional<Measurement> ModbusTransfer::Read() const {
  try {
    Readout r;
    std::string failed;
    if (const int error = ReadBlocks(r, failed); error != 0) {
      read_failure_ = fmt::format("the Modbus controller at {} failed {}: {}", Endpoint(), failed,
                                  error == ENOTCONN ? "call Activate() first"
                                                    : ModbusErrorText(error));
      return std::nullopt;
    }
    if (const std::string problem = StatusProblem(r); !problem.empty()) {
      read_failure_ = fmt::format("the Modbus controller at {} {}: {}", Endpoint(), problem,
                                  Describe(r));
      return std::nullopt;
    }
    if (!std::isfinite(r.position) || !std::isfinite(r.force)) {
      read_failure_ = fmt::format("the Modbus controller at {} reports a position or force that "
                                  "is not a number: {}; check the map's type, word_order and "
                                  "byte_order", Endpoint(), Describe(r));
      return std::nullopt;
    }
    read_failure_.clear();
    const double lab_time = options_.map.lab_time ? r.lab_time - lab_time_origin_
                            : clock_started_      ? WallSinceActivate()
                                                  : 0.0;
    return Measurement{r.position, r.force, lab_time};
  } catch (const std::exception& e) {
    try {
      read_failure_ = e.what();
    } catch (...) {
    }
  } catch (...) {
  }
  if (read_failure_.empty()) read_failure_ = "the position could not be read";
  return std::nullopt;
}

void ModbusTransfer::CheckFault(const Readout& r, const std::string& during) {
  if (Bit(r, options_.map.status_bits.fault)) {
    Fail(fmt::format("the Modbus controller at {} reports a fault (status bit {}) {}: {}; clear "
                     "the fault at the controller before resuming",
                     Endpoint(), options_.map.status_bits.fault, during, Describe(r)),
         false);
  }
}

double ModbusTransfer::WallSinceActivate() const { return Seconds(Clock::now() - activated_at_); }

void ModbusTransfer::Activate() {
  if (ctx_ == nullptr) Connect();
  const RegisterMap& m = options_.map;
  Readout r = ReadRegisters("the state before enabling");
  CheckFault(r, "before the test starts");
  if (m.hold_coil) WriteCoil(*m.hold_coil, false, "release the hold");
  if (m.enable_coil) WriteCoil(*m.enable_coil, true, "enable the drive");
  // Wait until the controller shows enabled and not holding.
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  const int enabled = m.status_bits.enabled, holding = m.status_bits.holding;
  for (;;) {
    r = ReadRegisters("the status after enabling");
    CheckFault(r, "while enabling");
    const bool ready = (enabled < 0 || Bit(r, enabled)) && !Bit(r, holding);
    if (ready || !m.status) break;
    if (Clock::now() >= deadline) {
      Fail(fmt::format("the Modbus controller at {} did not report enabled (bit {}) and not "
                       "holding (bit {}) within {} s after the enable coil was set: {}",
                       Endpoint(), enabled, holding, options_.ack_timeout, Describe(r)),
           true);
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
  }
  if (!std::isfinite(r.position)) {
    Fail(fmt::format("the Modbus controller at {} reports a position that is not a number: {}; "
                     "check the map's type, word_order and byte_order", Endpoint(), Describe(r)),
         true);
  }
  last_ack_ = r.ack;
  if (!clock_started_) {
    clock_started_ = true;
    activated_at_ = Clock::now();
    lab_time_origin_ = r.lab_time;
  }
  first_exchange_ = true;
  read_failure_.clear();
  active_ = true;
}

Measurement ModbusTransfer::Execute(double command) {
  const RegisterMap& m = options_.map;
  if (!active_ || ctx_ == nullptr) {
    throw TransferError(fmt::format(
        "the Modbus controller at {} is not active (not activated, holding, or the connection "
        "was lost): command {} {} not sent; call Activate() first",
        Endpoint(), command, m.units.length_name));
  }
  if (!read_failure_.empty()) {
    throw TransferError(fmt::format(
        "command {} {} not sent: the actuator's position could not be read before moving ({}); "
        "hybridtest does not move an actuator it cannot see. Check the link and the controller, "
        "then start again (Activate; `hybridtest resume` again)",
        command, m.units.length_name, read_failure_));
  }
  const std::uint64_t sequence = (last_ack_ + 1) % m.sequence_modulus();
  // 1. Command and sequence in one write (function 16).
  const RegisterBlock block = CommandBlock(m);
  std::uint16_t words[8] = {};
  EncodeValue(m, m.command, command, words + (m.command.address - block.start));
  EncodeValue(m, m.sequence, static_cast<double>(sequence), words + (m.sequence.address - block.start));
  ++requests_;
  if (modbus_write_registers(ctx_, block.start, block.count, words) != block.count) {
    FailRequest(fmt::format("to accept command {} {} with sequence {} (write of holding registers "
                            "{}–{})", command, m.units.length_name, sequence, block.start,
                            block.start + block.count - 1));
  }
  // 2. Poll until the controller acknowledges this sequence.
  const std::string waiting = fmt::format("while waiting for the ack of command {} {} (sequence {})",
                                          command, m.units.length_name, sequence);
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  Readout r;
  for (;;) {
    r = ReadRegisters(waiting);
    CheckFault(r, waiting);
    if (m.status && m.status_bits.enabled >= 0 && !Bit(r, m.status_bits.enabled)) {
      Fail(fmt::format("the Modbus controller at {} dropped the enable (status bit {}) {}: {}",
                       Endpoint(), m.status_bits.enabled, waiting, Describe(r)), false);
    }
    if (Bit(r, m.status_bits.holding)) {
      Fail(fmt::format("the Modbus controller at {} reports holding (status bit {}) {}: {}; it "
                       "holds on its own (an operator, an interlock or its watchdog) and the test "
                       "stops. Find out why it holds, then `hybridtest resume`",
                       Endpoint(), m.status_bits.holding, waiting, Describe(r)), false);
    }
    if (r.ack == sequence) break;
    // The link works but the controller does not do what it should: hold, then stop.
    if (r.ack != last_ack_) {
      Hold();
      Fail(fmt::format("the Modbus controller at {} acknowledged sequence {}, expected {} (or the "
                       "previous {} while moving) {}: {}; is another client writing to it? The "
                       "hold coil was set", Endpoint(), r.ack, sequence, last_ack_, waiting,
                       Describe(r)), false);
    }
    if (Clock::now() >= deadline) {
      Hold();
      Fail(fmt::format("the Modbus controller at {} did not acknowledge within {} s {}: last read "
                       "{}; the hold coil was set", Endpoint(), options_.ack_timeout, waiting,
                       Describe(r)), false);
    }
    if (options_.poll_interval > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
    }
  }
  last_ack_ = sequence;
  // 3. The first exchange must be plausible (catches a wrong word or byte order).
  if (first_exchange_) {
    const bool position_ok = std::abs(r.position - command) <= *options_.position_tolerance;
    const bool force_ok = std::abs(r.force) <= *options_.force_plausible;  // false for NaN
    if (!position_ok || !force_ok) {
      Fail(fmt::format("implausible first measurement from the Modbus controller at {}: command "
                       "{} {}, {}; expected the position within {} {} of the command and "
                       "|force| ≤ {} {}; check the map (type, word_order, byte_order, scale, "
                       "units) against the controller's manual",
                       Endpoint(), command, m.units.length_name, Describe(r),
                       *options_.position_tolerance, m.units.length_name,
                       *options_.force_plausible, m.units.force_name), false);
    }
    first_exchange_ = false;
  }
  // 4. Every exchange: the settled actuator must be where it was sent.
  const double following = std::abs(command - r.position);
  if (!(following <= *options_.following_error)) {
    Hold();
    const double metres = m.units.metres_per_length_unit;
    throw SafetyStop(
        "following_error", following * metres, *options_.following_error * metres, -1, -1, {},
        fmt::format("The Modbus controller at {} acknowledged command {} {} (sequence {}) but "
                    "measured position {} {}: |command − position| = {} {} > following_error {} "
                    "{} ({}). The actuator is not where it was sent (blocked or slipping, a drive "
                    "that ignores commands, a position sensor fault); the hold coil was set. To "
                    "proceed: find the cause at the controller; the limit is "
                    "transfer.following_error (the map's length unit; default the slot's "
                    "safety.max_increment)",
                    Endpoint(), command, m.units.length_name, sequence, r.position,
                    m.units.length_name, following, m.units.length_name,
                    *options_.following_error, m.units.length_name, Describe(r)));
  }
  const double lab_time = m.lab_time ? r.lab_time - lab_time_origin_ : WallSinceActivate();
  return Measurement{r.position, r.force, lab_time};
}

void ModbusTransfer::Hold() noexcept {
  active_ = false;
  if (ctx_ == nullptr || !options_.map.hold_coil) return;
  SetResponseTimeout(options_.hold_timeout);
  ++requests_;
  if (modbus_write_bit(ctx_, *options_.map.hold_coil, 1) != 1) {
    // Best effort: if the hold did not get through, drop the connection; the controller must
    // hold when its client goes away.
    Close();
    return;
  }
  SetResponseTimeout(options_.response_timeout);
}

void ModbusTransfer::Deactivate() {
  if (ctx_ == nullptr) return;
  active_ = false;
  const RegisterMap& m = options_.map;
  try {
    if (m.hold_coil) WriteCoil(*m.hold_coil, true, "hold before disabling");
    if (m.enable_coil) WriteCoil(*m.enable_coil, false, "disable the drive");
  } catch (...) {
    Close();
    throw;
  }
  Close();
}

}  // namespace hybridtest::transfer::modbus
