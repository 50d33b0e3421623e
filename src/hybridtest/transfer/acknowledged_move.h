#pragma once
// AcknowledgedMove: the move of a controller that acknowledges a settled command (a PLC over
// Modbus registers, a TwinCAT PLC over ADS symbols), written once (docs/safety.md, "The
// acknowledged move of a PLC"). A protocol supplies only its AckController: how to write the
// commands with their sequence, how to read what came back, how to hold, and the words of its
// messages (register or symbol names). The sequence, the deadlines, the checks and the
// messages are here.
//
// One Move(commands, io) for n actuators, commands in the bench's length unit:
//   0. refuses (TransferError, nothing sent) a wrong number of commands, a transfer that is not
//      active, or one whose last read without moving failed (resume must see the actuator);
//   1. the sequence of actuator k is s_k = (a_k + 1) mod modulus_k, a_k its last ack;
//      io.Write(commands, s);
//   2. io.Read() until every actuator's ack equals s_k, at most `ack_timeout` [s] after the
//      write, io.Wait() and a pause of `poll_interval` [s] between two reads. Every read checks,
//      in this order: a fault on any actuator, a dropped enable, holding, then an ack that is
//      neither s_k nor a_k (another client writes), then the deadline;
//   3. the first exchange after Start(): |position − command| ≤ position_tolerance and
//      |force| ≤ force_plausible (a wrong word order, scale or unit shows here; NaN fails);
//   4. every exchange: following error and stale acknowledgement (SettledReadingCheck,
//      safety_settled_reading.h; SafetyStop, value and limit in [m]).
// Every failure from step 1 on calls io.Hold() (best effort, never throws) before it throws:
// TransferError for 2 and 3, SafetyStop for 4, and whatever io.Write, io.Read or io.Wait throw
// passes unchanged after the hold. After a failure the next Move() refuses until Start(), as it
// does while the protocol says it is not active.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/core.h>

#include "hybridtest/transfer/controller_options.h"
#include "hybridtest/transfer/safety_settled_reading.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// "1.5" for one value, "[1.5, 2]" for several: the values of the messages.
template <class T>
std::string ValueList(std::span<const T> values) {
  std::string text;
  for (const T& v : values) text += (text.empty() ? "" : ", ") + fmt::format("{}", v);
  return values.size() == 1 ? text : "[" + text + "]";
}

// One actuator's part of one read of the controller.
struct AckReading {
  double position = 0.0;  // Unit: bench length unit.
  double force = 0.0;     // Unit: bench force unit.
  std::uint64_t ack = 0;  // the sequence of the last command the controller settled
  bool fault = false;     // false where the controller does not report it
  bool enabled = true;    // true where the controller does not report it
  bool holding = false;   // false where the controller does not report it
};

// What a protocol supplies. Each call may throw TransferError (a failed request), naming the
// controller and the request; Hold() never throws.
class AckController {
 public:
  enum class Flag { kFault, kEnabled, kHolding };

  virtual ~AckController() = default;
  // Sends every actuator's command (bench length unit) with its sequence.
  virtual void Write(std::span<const double> commands,
                     std::span<const std::uint64_t> sequences) = 0;
  // Reads every actuator once into `out` (resized to n). `why` says what it waits for.
  virtual void Read(std::vector<AckReading>& out, const std::string& why) = 0;
  // Between two reads while waiting for the acks (e.g. a watchdog's heartbeat).
  virtual void Wait() {}
  // Every actuator holds (best effort); the transfer is no longer active.
  virtual void Hold() noexcept = 0;

  // The words of the messages.
  // The controller: "the Modbus controller at 127.0.0.1:502 unit 1".
  virtual std::string Name() const = 0;
  // Actuator k's part of the controller: Name(), or Name() and the actuator when n > 1.
  virtual std::string Subject(std::size_t k) const = 0;
  // Actuator k in the last Read(), with where each value was read.
  virtual std::string Describe(std::size_t k) const = 0;
  // Where a flag shows as it stops the move: "status bit 1", "GVL_Hybrid.bFault = TRUE".
  virtual std::string Where(Flag flag, std::size_t k) const = 0;
  // The sequences sent: "sequence 2", "sequences [2, 2]", "GVL_Hybrid.nCommandSeq = 2".
  virtual std::string Sequences(std::span<const std::uint64_t> sequences) const = 0;
  // An ack read for actuator k: "sequence 3", "GVL_Hybrid.nAckSeq = 3".
  virtual std::string Ack(std::size_t k, std::uint64_t ack) const = 0;
  // What Hold() did: "the hold coil was set", "GVL_Hybrid.bHold was set (every actuator holds)".
  virtual std::string Held() const = 0;
  // How to fix an implausible first measurement: "check the map (type, word_order, …)".
  virtual std::string PlausibilityHint() const = 0;
};

class AcknowledgedMove {
 public:
  AcknowledgedMove() = default;
  // `o`: the controller's options, resolved in place (ResolveControllerOptions; `who` begins
  // its messages). `moduli`: one per actuator, the number of distinct sequences (65536 for a
  // uint16 register). `shared_status`: the fault, enable, holding and ack are one for every
  // actuator (the messages then name the controller, not an actuator). Throws ConfigError.
  AcknowledgedMove(ControllerOptions& o, const BenchUnits& units,
                   std::vector<std::uint64_t> moduli, bool shared_status, std::string_view who);

  // After the controller was enabled: its acks now (one per actuator). The next Move() is the
  // first exchange (plausibility), with no previous one (stale acknowledgement).
  void Start(std::span<const std::uint64_t> acks);
  // Steps 0–4 above; `out` (one per actuator) gets the position and force of the read that
  // carried the acks, lab_time 0 (the protocol knows its clock). `active`: the transfer was
  // activated and has not held since; `read_failure`: why its last read without moving failed
  // ("" if it did not).
  void Move(std::span<const double> commands, std::span<Measurement> out, AckController& io,
            bool active, const std::string& read_failure);

  std::size_t num_actuators() const { return moduli_.size(); }

 private:
  // io.Hold(), then throws TransferError `message`.
  [[noreturn]] void Fail(AckController& io, const std::string& message);
  // Steps 2, 3 and 4 (step 1 done).
  void AwaitAcks(AckController& io, const std::string& waiting);
  void CheckPlausible(std::span<const double> commands, AckController& io);
  void CheckSettled(std::span<const double> commands, AckController& io);
  // Who to name for actuator k's status or ack.
  std::string Who(const AckController& io, std::size_t k) const;

  double ack_timeout_ = 0.0;        // [s]
  double poll_interval_ = 0.0;      // [s]
  double position_tolerance_ = 0.0; // bench length unit
  double force_plausible_ = 0.0;    // bench force unit
  BenchUnits units_;
  std::vector<std::uint64_t> moduli_;
  bool shared_status_ = false;
  SettledReadingCheck settled_;
  std::vector<std::uint64_t> last_ack_;  // per actuator: the ack before the next command
  std::vector<std::uint64_t> sequence_;  // per actuator: the sequence of this move
  std::vector<AckReading> reading_;      // the last read
  bool first_exchange_ = true;
  bool failed_ = false;                  // a Move() failed since Start()
};

}  // namespace hybridtest::transfer
