#pragma once
// ModbusTransfer: a TransferSystem that drives a lab controller (a PLC runtime, a servo drive,
// an actuator controller) over Modbus/TCP with libmodbus, through a RegisterMap
// (register_map.h; docs/modbus.md for the lab engineer).
//
// One Execute(commands, out) is the acknowledged move of a PLC (acknowledged_move.h; docs/
// safety.md, "The acknowledged move of a PLC"), which owns the sequence, the deadlines, the
// checks and the hold on every failure. The Modbus parts (modbus_execute.cc), per actuator:
//   1. one write (function 16) of the command and its sequence number s, the previous ack plus
//      1 modulo the sequence register's range (65536 for uint16);
//   2. reads of the readout registers (function 4 / 3): position, force, ack, and the status
//      bits of the map (fault, enabled, holding; a bit at -1 or `status: none` is not
//      reported, so never stops the move);
//   3. the hold: the hold coil of every actuator (Hold());
//   4. the measurement: position and force (bench units), lab time (the bench clock's
//      register minus its value at Activate, or else the wall time since Activate) [s].
// Its messages name host:port, the registers and bits, and the last values read. After a
// communication failure (response timeout, lost connection, garbled answer) the connection is
// closed: its state is unknown, and the controller must hold when its client goes away. After
// a Modbus exception the connection stays open, so that the hold coil still reaches the
// controller. The default following error is four settling windows, 4 × `settle_tolerance`,
// at most the slot's safety.max_increment (modbus_config.h); the first exchange's plausibility
// defaults to 1 mm and 1 MN.
//
// ReadAll() reads the readout registers once (no write, so no move) and returns every position
// and force in bench units; it never throws. It returns nullopt when it cannot read, when a value
// is not finite, or when the status shows a fault, no enable or holding; it then remembers why,
// and the next Execute() refuses to move (TransferError) until the next Activate(). That is
// the choice for resume: a resume that cannot see where the actuator is must not re-impose the
// last command blind in one move (docs/modbus.md, "Resuming a run").
//
// Lifecycle: Activate() connects (bounded by connect_timeout), reads the current ack and
// status (a fault bit refuses to start), clears the hold coil, sets the enable coil and waits
// until the status shows enabled and not holding. Hold() sets the hold coil (bounded by
// hold_timeout) and never throws; Execute() refuses to move until the next Activate().
// Deactivate() sets the hold coil, clears the enable coil and disconnects.
// Every request is bounded by libmodbus's response timeout; nothing blocks without a bound.
//
// Several actuators (`options.maps`, one RegisterMap each; register_map.h and
// docs/modbus.md, "Several actuators"): num_actuators() = n and Execute(commands, out) writes
// every actuator's command and its own sequence (one write per contiguous run of command
// blocks, so one write when they follow each other) before it reads anything, then reads every
// actuator's readout until each acknowledges its own sequence. Every message names the
// actuator ("actuator 2", as the journal's `<name>_a2_…` channels); a failure on any actuator
// sets the hold coil of every actuator. Hold() and Deactivate() set every hold coil (a shared
// coil once), Activate() enables every actuator and waits until each shows enabled and not
// holding. Probe() looks at every actuator and names the first with a problem.
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/acknowledged_move.h"
#include "hybridtest/transfer/controller_options.h"
#include "hybridtest/transfer/modbus/register_map.h"
#include "hybridtest/transfer/transfer_system.h"

struct _modbus;  // libmodbus's context (modbus_t), kept out of this header

namespace hybridtest::transfer::modbus {

// The timeouts, the first exchange's plausibility, the settling window and the following
// errors are the ControllerOptions (controller_options.h), in the unit of maps[0].
struct ModbusOptions : ControllerOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 502;
  int unit_id = 1;                     // Modbus unit identifier (0..247; 255 for "any")
  // One register map per actuator (register_map.h); by default one actuator on the default
  // profile. Units, word and byte order are the controller's: those of maps[0].
  std::vector<RegisterMap> maps{RegisterMap{}};
};

class ModbusTransfer final : public TransferSystem {
 public:
  // Does not connect (Activate() does). Throws ConfigError for bad timeouts, unit id or map.
  explicit ModbusTransfer(ModbusOptions options);
  ~ModbusTransfer() override;
  ModbusTransfer(const ModbusTransfer&) = delete;
  ModbusTransfer& operator=(const ModbusTransfer&) = delete;

  void Activate() override;
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  int num_actuators() const override { return static_cast<int>(maps_.size()); }
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return maps_[0].units; }
  std::string Describe() const override;
  // Every actuator's position and force now (bench units), and the lab time [s], read without
  // writing a command. nullopt (and the next Execute() refuses) if not connected, a read fails,
  // a value is not finite, or any actuator's status shows fault, no enable or holding. Never
  // throws.
  std::optional<std::vector<Measurement>> ReadAll() override;
  // Connects if needed (bounded by connect_timeout) and reads the readout registers once:
  // no write, no coil, so nothing moves and no drive is enabled (modbus_probe.cc). The
  // problem names a fault, holding, or a value that is not a number (a word or byte order
  // slip). The connection stays open for Activate(). Throws TransferError when the controller
  // cannot be reached or read.
  std::optional<ProbeReading> Probe() override;

  const ModbusOptions& options() const { return options_; }
  bool is_connected() const { return ctx_ != nullptr; }
  // Requests (reads and writes) sent since construction; a measure of polling.
  long requests() const { return requests_; }

 private:
  class Controller;  // the Modbus side of the acknowledged move (modbus_execute.cc)

  // What one read of the readout blocks gave.
  struct Readout {
    double position = 0.0, force = 0.0, lab_time = 0.0;  // bench units, [s]
    std::uint64_t ack = 0;
    int status = -1;  // -1: no status register
  };

  std::string Endpoint() const;
  // "the Modbus controller at HOST:PORT unit U" (one actuator), "...: actuator k+1" (several).
  std::string Subject(std::size_t k) const;
  std::string Describe(const Readout& r, std::size_t k) const;
  void Connect();
  void Close() noexcept;
  void SetResponseTimeout(double seconds) noexcept;
  // Throws TransferError "<what>: <libmodbus error>"; closes unless it was a Modbus exception.
  [[noreturn]] void FailRequest(const std::string& what);  // errno
  [[noreturn]] void FailRequest(const std::string& what, int error);
  [[noreturn]] void Fail(const std::string& message, bool close);
  void WriteCoil(int address, bool value, const std::string& why);
  // One read of the readout blocks into `r` (one Readout per actuator): 0, or the errno of the
  // failed request (`failed` names it). Never closes the connection.
  int ReadBlocks(std::vector<Readout>& r, std::string& failed);
  // ReadBlocks, or FailRequest.
  std::vector<Readout> ReadRegisters(const std::string& why);
  static bool Bit(const Readout& r, int bit) {
    return bit >= 0 && r.status >= 0 && (r.status >> bit) & 1;
  }
  // A fault bit on any actuator: (several actuators: every one holds) TransferError.
  void CheckFault(const std::vector<Readout>& r, const std::string& during);
  // "" if actuator k's status is fit to move (no fault, enabled, not holding); else what is wrong.
  std::string StatusProblem(const Readout& r, std::size_t k) const;
  // Hold() when several actuators share the controller (one stops, every one holds).
  void HoldIfSeveral() noexcept;
  double WallSinceActivate() const;

  ModbusOptions options_;
  std::vector<RegisterMap> maps_;     // one per actuator
  std::vector<WriteBlock> writes_;    // the writes of every actuator's command and sequence
  std::vector<RegisterBlock> reads_;  // the reads of every actuator's readout
  // The registers last read, by table, at their protocol address (65536 each).
  std::vector<std::uint16_t> input_, holding_;
  _modbus* ctx_ = nullptr;
  bool active_ = false;              // Activate() done and no Hold() since
  AcknowledgedMove move_;            // the sequence, the checks and the last acks
  double lab_time_origin_ = 0.0;     // bench clock at Activate [s]
  std::chrono::steady_clock::time_point activated_at_{};
  bool clock_started_ = false;
  long requests_ = 0;                // Read() counts its request too
  // Why the last Read() gave nothing; Execute() refuses while it is set (until Activate()).
  std::string read_failure_;
};

}  // namespace hybridtest::transfer::modbus
