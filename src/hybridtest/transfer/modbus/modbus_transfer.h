#pragma once
// ModbusTransfer: a TransferSystem that drives a lab controller (a PLC runtime, a servo drive,
// an actuator controller) over Modbus/TCP with libmodbus, through a RegisterMap
// (register_map.h; docs/modbus.md for the lab engineer).
//
// One Execute(commands, out), per actuator:
//   1. one write (function 16) of the command and its sequence number s, where s is the
//      previous one plus 1 modulo 65536 (uint16 sequence);
//   2. reads of the readout registers (function 4 / 3), repeated every `poll_interval` until
//      the acknowledged sequence equals s (the controller has settled and sampled), at most
//      `ack_timeout` in total; while it still shows the previous sequence the move is running;
//   3. the measurement: position and force (bench units), lab time (the bench clock's
//      register minus its value at Activate, or else the wall time since Activate) [s].
// It raises TransferError naming host:port, the register and the last values read on: an ack
// timeout, any other ack, a fault bit, a drive that is no longer enabled, a controller that
// reports holding, a Modbus exception, a lost connection or a libmodbus response timeout. The
// status bits (fault, enabled, holding) are checked on every read of every exchange, the last
// one included: a controller that faults, drops the enable or holds on its own mid-run stops
// the run even if it still acknowledges.
//
// Following error and stale acknowledgement (transfer/safety_settled_reading.h, the check a
// Python bench driver gets too): once the ack is in, |command − measured position| must not
// exceed `following_error` (bench length unit; default four settling windows, 4 ×
// `settle_tolerance`, at most the slot's safety.max_increment, see modbus_config.h), and a
// command that moved by more than two settling windows must not be acknowledged with the
// previous exchange's position, bit for bit (a controller that acks before it updates its
// data). Beyond either Execute() sets the hold coil and throws SafetyStop (limit
// "following_error" or "stale_acknowledgement", value and limit in [m]) naming the command and
// the measured position: an actuator that is not where it was sent means the specimen's force
// belongs to another displacement, and every later increment check starts from a wrong place. When the link itself still works (ack
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
// actuator's readout until each acknowledges its own sequence, within ack_timeout. Every check
// above applies to every actuator and its message names it ("actuator 2", as the journal's
// `<name>_a2_…` channels); a fault, a dropped enable or a controller that holds on one actuator
// sets the hold coil of every actuator before the TransferError, as do an ack timeout and an
// unexpected ack. Hold() and Deactivate() set every hold coil (a shared coil once), Activate()
// enables every actuator and waits until each shows enabled and not holding. Probe() looks at
// every actuator and names the first with a problem.
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/controller_options.h"
#include "hybridtest/transfer/modbus/register_map.h"
#include "hybridtest/transfer/transfer_system.h"
#include "hybridtest/transfer/safety_settled_reading.h"

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
  std::optional<std::vector<Measurement>> ReadAll() const override;
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
  int ReadBlocks(std::vector<Readout>& r, std::string& failed) const;
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
  mutable std::vector<std::uint16_t> input_, holding_;
  _modbus* ctx_ = nullptr;
  bool active_ = false;              // Activate() done and no Hold() since
  bool first_exchange_ = true;       // the next Execute() is checked for plausibility
  SettledReadingCheck settled_;      // following error and stale ack, per actuator
  std::vector<std::uint64_t> last_ack_;  // per actuator: the ack before the next command
  double lab_time_origin_ = 0.0;     // bench clock at Activate [s]
  std::chrono::steady_clock::time_point activated_at_{};
  bool clock_started_ = false;
  mutable long requests_ = 0;        // Read() counts its request too
  // Why the last Read() gave nothing; Execute() refuses while it is set (until Activate()).
  mutable std::string read_failure_;
};

}  // namespace hybridtest::transfer::modbus
