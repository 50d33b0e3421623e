// See modbus_transfer.h: construction, the lifecycle (Activate, Hold, Deactivate) and reads
// without a move. The connection and its requests are in modbus_link.cc, Execute in
// modbus_execute.cc, Probe in modbus_probe.cc.
#include "hybridtest/transfer/modbus/modbus_transfer.h"

#include <errno.h>
#include <fmt/core.h>
#include <modbus.h>

#include <cmath>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/modbus/modbus_link.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer::modbus {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// "holding registers 0–1, 3–4" for a field of every actuator.
template <class F>
std::string EveryActuator(const std::vector<RegisterMap>& maps, F field) {
  std::string text = DescribeField(field(maps[0]));
  for (std::size_t k = 1; k < maps.size(); ++k) {
    const std::string next = DescribeField(field(maps[k]));
    text += ", " + next.substr(next.find_last_of(' ') + 1);
  }
  return text;
}

}  // namespace

ModbusTransfer::ModbusTransfer(ModbusOptions options)
    : options_(std::move(options)), input_(65536), holding_(65536) {
  const ModbusOptions& o = options_;
  if (o.maps.empty()) {
    throw ConfigError("modbus transfer: map: no register map; give one per actuator (the "
                      "default profile for one actuator)");
  }
  const RegisterMap& first = o.maps[0];
  if (o.unit_id < 0 || o.unit_id > 255) {
    throw ConfigError(fmt::format("modbus transfer: unit_id = {}: expected 0..255 (usually 1; "
                                  "255 addresses a Modbus/TCP device directly)", o.unit_id));
  }
  for (const RegisterMap& m : o.maps) {
    const BenchUnits& u = m.units;
    if (u.length_name != first.units.length_name || u.force_name != first.units.force_name ||
        m.word_order != first.word_order || m.byte_order != first.byte_order) {
      throw ConfigError("modbus transfer: map: every actuator's map must have the controller's "
                        "units, word_order and byte_order (those of actuator 1)");
    }
  }
  ValidateRegisterMaps(o.maps, "modbus transfer: map");
  std::vector<std::uint64_t> moduli;
  for (const RegisterMap& m : o.maps) moduli.push_back(m.sequence_modulus());
  move_ = AcknowledgedMove(options_, first.units, std::move(moduli), false, "modbus transfer");
  maps_ = o.maps;
  writes_ = CommandWrites(maps_);
  reads_ = ReadoutBlocks(maps_);
}

ModbusTransfer::~ModbusTransfer() { Close(); }

std::string ModbusTransfer::Describe() const {
  const RegisterMap& m = maps_[0];
  if (maps_.size() == 1) {
    return fmt::format("Modbus/TCP controller at {} ({}, {}; command at {}, ack at {})",
                       Endpoint(), m.units.length_name, m.units.force_name,
                       DescribeField(m.command), DescribeField(m.ack));
  }
  return fmt::format(
      "Modbus/TCP controller at {} ({}, {}; {} actuators; commands at {}, acks at {})",
      Endpoint(), m.units.length_name, m.units.force_name, maps_.size(),
      EveryActuator(maps_, [](const RegisterMap& a) { return a.command; }),
      EveryActuator(maps_, [](const RegisterMap& a) { return a.ack; }));
}

std::string ModbusTransfer::Describe(const Readout& r, std::size_t k) const {
  const RegisterMap& m = maps_[k];
  std::string text = fmt::format("ack {} ({}), position {} {} ({}), force {} {} ({})", r.ack,
                                 DescribeField(m.ack), r.position, m.units.length_name,
                                 DescribeField(m.position), r.force, m.units.force_name,
                                 DescribeField(m.force));
  if (r.status >= 0) text += fmt::format(", status 0x{:04x} ({})", r.status, DescribeField(*m.status));
  return text;
}

std::string ModbusTransfer::StatusProblem(const Readout& r, std::size_t k) const {
  const StatusBits& b = maps_[k].status_bits;
  if (!maps_[k].status) return "";
  if (Bit(r, b.fault)) return fmt::format("reports a fault (status bit {})", b.fault);
  if (b.enabled >= 0 && !Bit(r, b.enabled)) {
    return fmt::format("does not report the drive enabled (status bit {})", b.enabled);
  }
  if (Bit(r, b.holding)) return fmt::format("reports holding (status bit {})", b.holding);
  return "";
}

std::optional<std::vector<Measurement>> ModbusTransfer::ReadAll() {
  try {
    std::vector<Readout> r;
    std::string failed;
    if (const int error = ReadBlocks(r, failed); error != 0) {
      read_failure_ = fmt::format("the Modbus controller at {} failed {}: {}", Endpoint(), failed,
                                  error == ENOTCONN ? "call Activate() first"
                                                    : ModbusErrorText(error));
      return std::nullopt;
    }
    std::vector<Measurement> out;
    for (std::size_t k = 0; k < r.size(); ++k) {
      if (const std::string problem = StatusProblem(r[k], k); !problem.empty()) {
        read_failure_ = fmt::format("{} {}: {}", Subject(k), problem, Describe(r[k], k));
        return std::nullopt;
      }
      if (!std::isfinite(r[k].position) || !std::isfinite(r[k].force)) {
        read_failure_ = fmt::format("{} reports a position or force that is not a number: {}; "
                                    "check the map's type, word_order and byte_order",
                                    Subject(k), Describe(r[k], k));
        return std::nullopt;
      }
      const double lab_time = maps_[0].lab_time ? r[k].lab_time - lab_time_origin_
                              : clock_started_  ? WallSinceActivate()
                                                : 0.0;
      out.push_back(Measurement{r[k].position, r[k].force, lab_time});
    }
    read_failure_.clear();
    return out;
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

void ModbusTransfer::HoldIfSeveral() noexcept {
  if (maps_.size() > 1) Hold();
}

void ModbusTransfer::CheckFault(const std::vector<Readout>& r, const std::string& during) {
  for (std::size_t k = 0; k < r.size(); ++k) {
    const int fault = maps_[k].status_bits.fault;
    if (!Bit(r[k], fault)) continue;
    HoldIfSeveral();
    Fail(fmt::format("{} reports a fault (status bit {}) {}: {}; {}clear the fault at the "
                     "controller before resuming",
                     Subject(k), fault, during, Describe(r[k], k),
                     maps_.size() > 1 ? "every actuator's hold coil was set; " : ""),
         false);
  }
}

double ModbusTransfer::WallSinceActivate() const { return Seconds(Clock::now() - activated_at_); }

void ModbusTransfer::Activate() {
  if (ctx_ == nullptr) Connect();
  std::vector<Readout> r = ReadRegisters("the state before enabling");
  CheckFault(r, "before the test starts");
  for (int coil : HoldCoils(maps_)) WriteCoil(coil, false, "release the hold");
  for (int coil : EnableCoils(maps_)) WriteCoil(coil, true, "enable the drive");
  // Wait until every actuator shows enabled and not holding.
  const auto deadline = Clock::now() + std::chrono::duration<double>(options_.ack_timeout);
  for (;;) {
    r = ReadRegisters("the status after enabling");
    CheckFault(r, "while enabling");
    std::size_t waiting = maps_.size();
    for (std::size_t k = 0; k < maps_.size() && waiting == maps_.size(); ++k) {
      const StatusBits& b = maps_[k].status_bits;
      const bool ready = (b.enabled < 0 || Bit(r[k], b.enabled)) && !Bit(r[k], b.holding);
      if (!ready && maps_[k].status) waiting = k;
    }
    if (waiting == maps_.size()) break;
    if (Clock::now() >= deadline) {
      const StatusBits& b = maps_[waiting].status_bits;
      Fail(fmt::format("{} did not report enabled (bit {}) and not holding (bit {}) within {} s "
                       "after the enable coil was set: {}", Subject(waiting), b.enabled,
                       b.holding, options_.ack_timeout, Describe(r[waiting], waiting)),
           true);
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.poll_interval));
  }
  std::vector<std::uint64_t> acks;
  for (std::size_t k = 0; k < maps_.size(); ++k) {
    if (!std::isfinite(r[k].position)) {
      Fail(fmt::format("{} reports a position that is not a number: {}; check the map's type, "
                       "word_order and byte_order", Subject(k), Describe(r[k], k)),
           true);
    }
    acks.push_back(r[k].ack);
  }
  if (!clock_started_) {
    clock_started_ = true;
    activated_at_ = Clock::now();
    lab_time_origin_ = r[0].lab_time;
  }
  move_.Start(acks);
  read_failure_.clear();
  active_ = true;
}

void ModbusTransfer::Hold() noexcept {
  active_ = false;
  if (ctx_ == nullptr) return;
  bool timeout_set = false;
  for (std::size_t k = 0; k < maps_.size(); ++k) {
    const RegisterMap& m = maps_[k];
    if (!m.hold_coil) continue;
    bool written = false;  // a shared coil once
    for (std::size_t j = 0; j < k; ++j) written |= maps_[j].hold_coil == m.hold_coil;
    if (written) continue;
    if (!timeout_set) SetResponseTimeout(options_.hold_timeout);
    timeout_set = true;
    ++requests_;
    if (modbus_write_bit(ctx_, *m.hold_coil, 1) != 1) {
      // Best effort: if a hold did not get through, drop the connection; the controller must
      // hold when its client goes away.
      Close();
      return;
    }
  }
  if (timeout_set) SetResponseTimeout(options_.response_timeout);
}

void ModbusTransfer::Deactivate() {
  if (ctx_ == nullptr) return;
  active_ = false;
  try {
    for (int coil : HoldCoils(maps_)) WriteCoil(coil, true, "hold before disabling");
    for (int coil : EnableCoils(maps_)) WriteCoil(coil, false, "disable the drive");
  } catch (...) {
    Close();
    throw;
  }
  Close();
}

}  // namespace hybridtest::transfer::modbus
