#pragma once
// ModbusTransfer: a TransferSystem that drives a lab controller (a PLC runtime, a servo drive,
// an actuator controller) over Modbus/TCP with libmodbus, through a RegisterMap
// (register_map.h; docs/modbus.md for the lab engineer).
//
// One Execute(command):
//   1. one write (function 16) of the command and its sequence number s, where s is the
//      previous one plus 1 modulo 65536 (uint16 sequence);
//   2. reads of the readout registers (function 4 / 3), repeated every `poll_interval` until
//      the acknowledged sequence equals s (the controller has settled and sampled), at most
//      `ack_timeout` in total; while it still shows the previous sequence the move is running;
//   3. the measurement: position and force (bench units), lab time (the bench clock's
//      register minus its value at Activate, or else the wall time since Activate) [s].
// It raises TransferError naming host:port, the register and the last values read on: an ack
// timeout, any other ack, a fault bit, a drive that is no longer enabled, a Modbus exception,
// a lost connection or a libmodbus response timeout. When the link itself still works (ack
// timeout, unexpected ack) it sets the hold coil first. After a communication failure
// (response timeout, lost connection, garbled answer) the connection is closed: its state is
// unknown, and the controller must hold when its client goes away. After a Modbus exception,
// a fault bit or a dropped enable the connection stays open, so that Hold() still reaches
// the controller.
//
// The first exchange after Activate() is checked for plausibility: the measured position must
// lie within `position_tolerance` of the command (default 1 mm) and the force be finite and
// within `force_plausible` (default 1 MN). A wrong word or byte order in the map turns a settled position into an
// absurd number (±1e±30, NaN), which this catches before the test goes on.
//
// Lifecycle: Activate() connects (bounded by connect_timeout), reads the current ack and
// status (a fault bit refuses to start), clears the hold coil, sets the enable coil and waits
// until the status shows enabled and not holding. Hold() sets the hold coil (bounded by
// hold_timeout) and never throws; Execute() refuses to move until the next Activate().
// Deactivate() sets the hold coil, clears the enable coil and disconnects.
// Every request is bounded by libmodbus's response timeout; nothing blocks without a bound.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/transfer/modbus/register_map.h"
#include "hybridtest/transfer/transfer_system.h"

struct _modbus;  // libmodbus's context (modbus_t), kept out of this header

namespace hybridtest::transfer::modbus {

struct ModbusOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 502;
  int unit_id = 1;                     // Modbus unit identifier (0..247; 255 for "any")
  RegisterMap map;                     // default profile unless configured
  double connect_timeout = 5.0;        // longest wait for the TCP connection. Unit: [s].
  double response_timeout = 1.0;       // longest wait for the answer to one request. Unit: [s].
  double ack_timeout = 5.0;            // longest wait for the ack of one command. Unit: [s].
  double hold_timeout = 0.5;           // longest wait for the answer to Hold()'s write. Unit: [s].
  double poll_interval = 0.0;          // pause between two reads while waiting. Unit: [s].
  // First exchange: the largest |position − command| and |force|. Unit: bench length and
  // force units. Unset: 1 mm and 1 MN, converted to the map's units.
  std::optional<double> position_tolerance;
  std::optional<double> force_plausible;
};

class ModbusTransfer final : public TransferSystem {
 public:
  // Does not connect (Activate() does). Throws ConfigError for bad timeouts, unit id or map.
  explicit ModbusTransfer(ModbusOptions options);
  ~ModbusTransfer() override;
  ModbusTransfer(const ModbusTransfer&) = delete;
  ModbusTransfer& operator=(const ModbusTransfer&) = delete;

  void Activate() override;
  Measurement Execute(double command) override;
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return options_.map.units; }
  std::string Describe() const override;

  const ModbusOptions& options() const { return options_; }
  bool is_connected() const { return ctx_ != nullptr; }
  // Requests (reads and writes) sent since construction; a measure of polling.
  long requests() const { return requests_; }

 private:
  // What one read of the readout blocks gave.
  struct Readout {
    double position = 0.0, force = 0.0, lab_time = 0.0;  // bench units, [s]
    std::uint64_t ack = 0;
    int status = -1;  // -1: no status register
  };

  std::string Endpoint() const;
  std::string Describe(const Readout& r) const;
  void Connect();
  void Close() noexcept;
  void SetResponseTimeout(double seconds) noexcept;
  // Throws TransferError "<what>: <libmodbus error>"; closes unless it was a Modbus exception.
  [[noreturn]] void FailRequest(const std::string& what);
  [[noreturn]] void Fail(const std::string& message, bool close);
  void WriteCoil(int address, bool value, const std::string& why);
  Readout Read(const std::string& why);
  bool Bit(const Readout& r, int bit) const { return bit >= 0 && r.status >= 0 && (r.status >> bit) & 1; }
  void CheckFault(const Readout& r, const std::string& during);
  double WallSinceActivate() const;

  ModbusOptions options_;
  _modbus* ctx_ = nullptr;
  bool active_ = false;              // Activate() done and no Hold() since
  bool first_exchange_ = true;       // the next Execute() is checked for plausibility
  std::uint64_t last_ack_ = 0;       // the ack the controller shows before the next command
  double lab_time_origin_ = 0.0;     // bench clock at Activate [s]
  std::chrono::steady_clock::time_point activated_at_{};
  bool clock_started_ = false;
  long requests_ = 0;
  std::vector<std::uint16_t> buffer_;
};

}  // namespace hybridtest::transfer::modbus
