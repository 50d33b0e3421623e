#pragma once
// TransferSystem: what moves a physical substructure. One or several actuator channels: position
// commands go out, measurements (position, force) come back. This is the hardware seam of
// hybridtest: a transfer system speaks the bench's own units (bench_units()); the setup
// transform of a PhysicalSubstructure converts to and from SI.
//
// Lifecycle (after ros2_control): construct (configure) → Activate() → Execute()* → Deactivate().
// Hold() may be called at any time, from any state, and must never throw.
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/common/clock.h"
#include "hybridtest/common/error.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::transfer {

// The units a bench speaks on the wire.
struct BenchUnits {
  double metres_per_length_unit = 1.0;   // 1e-3 for a bench that speaks [mm]
  double newtons_per_force_unit = 1.0;   // 1e3 for a bench that speaks [kN]
  std::string length_name = "m";
  std::string force_name = "N";
};

// What a bench returns after executing one command.
struct Measurement {
  double position = 0.0;  // measured actuator position. Unit: bench length unit.
  double force = 0.0;     // measured force at the load cell. Unit: bench force unit.
  double lab_time = 0.0;  // lab time since Activate() when the sample was taken. Unit: [s].
  // Reversals of the specimen force within this move (reversal_counter.h), if the transfer
  // system can see them (the emulated bench); 0 otherwise.
  long force_reversals = 0;
};

// What a bench tells about one of its actuators before anything moves, where it knows it.
struct ActuatorAnnouncement {
  std::optional<double> p0;            // zero-force actuator position. Unit: [m].
  std::optional<SafetyLimits> limits;  // the bench's own limits, SI (timeout not compared)
};

// What a bench tells about itself before anything moves, where it knows it: each actuator's
// position of zero specimen force and its own safety limits, SI. The runner checks its setup
// against these before the first command (docs/safety.md, "Before anything moves").
struct BenchAnnouncement {
  // In the transfer system's actuator order; empty, or fewer than num_actuators(): the bench
  // tells nothing about the rest.
  std::vector<ActuatorAnnouncement> actuators;
  std::string source;  // who announced it, for messages
};

// One look at the bench without moving it (no command written, no drive enabled).
struct ProbeReading {
  std::vector<Measurement> measurements;  // every actuator's, bench units; lab_time 0
  std::string status;       // the controller's status in words, e.g. "enabled, no fault"
  std::string problem;      // "" if the bench is fit to start; else what is wrong
};

class TransferSystem {
 public:
  virtual ~TransferSystem() = default;

  // Makes the bench ready to move (connect, handshake, enable). Throws TransferError.
  virtual void Activate() = 0;

  // Actuators this transfer system moves at once (n ≥ 1). Before Activate() a remote bench
  // may not know yet (its WELCOME tells): it answers what its configuration expects.
  virtual int num_actuators() const = 0;
  // Moves every actuator: commands (n, absolute actuator positions in the bench length unit,
  // actuator order) all go out before any measurement is awaited; waits until the bench has
  // settled, samples, and writes one measurement per actuator into out (n). Blocking, but never
  // without a bound: a bench that does not answer in time raises TransferError; sizes other
  // than n raise TransferError. Throws SafetyStop when the bench itself refuses a command for
  // safety reasons; a refused command moves no actuator.
  virtual void Execute(std::span<const double> commands, std::span<Measurement> out) = 0;

  // Two-phase moves (docs/multi-site.md): the Session proposes every physical substructure's
  // move of a trial before any moves, collects every verdict, and only then releases them.
  // Propose sends the commands (n, bench length unit, what Execute will be given) of the move
  // at (step, stage) and does not wait; AwaitVerdict waits for the answer and throws
  // SafetyStop if the bench refuses it (nothing moved anywhere), TransferError if it cannot
  // tell; Release lets an accepted move start (without waiting for it); the following
  // Execute with the same commands collects its measurement. A transfer system without its
  // own verdict (every local one: its safety gate is the caller's, checked before Propose)
  // keeps the defaults, which do nothing; Execute alone still works for every move.
  virtual void Propose(std::span<const double> /*commands*/, long /*step*/, int /*stage*/) {}
  virtual void AwaitVerdict() {}
  virtual void Release() {}
  // True for a transfer system that decides on proposals itself over a link (a site).
  virtual bool two_phase() const { return false; }
  // Called (with no argument) when this transfer system loses its link and starts waiting for
  // it, so the caller can hold the others. Default: never called.
  virtual void OnLinkLost(std::function<void()> /*hold_others*/) {}

  // Puts the bench in its safe state: hold at the last safe command. Never moves to a new
  // position, never returns to zero by itself, never throws.
  virtual void Hold() noexcept = 0;

  // Ends the session cleanly (holds first). Throws TransferError on a communication failure.
  virtual void Deactivate() = 0;

  // Units of Execute()'s commands and of the Measurements.
  virtual BenchUnits bench_units() const = 0;

  // One line for logs and reports, e.g. "emulated bench (cantilever 500x100x5 mm, E=210 GPa)".
  virtual std::string Describe() const = 0;
  // Every actuator's position and force (n measurements, bench units, actuator order), read
  // WITHOUT moving; nullopt if this transfer system cannot read every actuator so (resume then
  // re-imposes the last committed commands at once). Never throws. Not const: a remote bench
  // reads through an exchange on its link (a request, its sequence number, a reconnect).
  virtual std::optional<std::vector<Measurement>> ReadAll() { return std::nullopt; }
  // What the bench announces about itself (see BenchAnnouncement); may be empty. For a remote
  // bench, known only after Activate() (its WELCOME). Never throws.
  virtual BenchAnnouncement Announce() const { return {}; }
  // Reads position, force and status without moving and without enabling a drive, before
  // Activate(): nullopt if this transfer system cannot. Throws TransferError when it can but
  // the bench does not answer.
  virtual std::optional<ProbeReading> Probe() { return std::nullopt; }
  // State of an in-process bench for a run's checkpoint (runner/run_state.h); null if the
  // bench's state lives outside this process (a remote bench keeps its own and is not
  // restored). Throws hybridtest::Error on a state that does not fit.
  virtual nlohmann::json SaveState() const { return nullptr; }
  // Commands received over the bench's (restored) lifetime, if this transfer system counts
  // them (an in-process bench); the runner records it when a run stops.
  virtual std::optional<long> commands_received() const { return std::nullopt; }
  // Restores what SaveState() gave. On a resume the state may also carry
  // "commands_received_at_stop": what commands_received() gave when the run stopped (more than
  // the saved state knows: the commands of the interrupted step).
  virtual void RestoreState(const nlohmann::json& /*state*/) {}
  // Real time (decision 0015): from now on Execute() sends the command of the current tick
  // and returns the measurement of that tick at once, without settling; an emulated plant
  // advances its state to clock.Now() on every Execute. tick: the loop's step [s]; `clock`
  // must outlive the run. A transfer system that cannot run paced refuses with ConfigError.
  virtual void StartPaced(double /*tick*/, const Clock& /*clock*/) {
    throw ConfigError(Describe() + ": this transfer system cannot run in real time (paced); "
                      "use `transfer: {type: rt_plant, ...}` or remove the `real_time:` block");
  }
  // True if StartPaced works (every actuator then runs on the loop's clock). A real-time run
  // asks before anything moves and refuses a transfer system that cannot (a lab-time bench).
  virtual bool can_run_paced() const { return false; }
  // For the delay check of a real-time run (runner/delay_stability.h): the phase delay of the
  // command → position response at ω [rad/s] in a paced run with step `tick` [s] (a
  // continuous plant's zero-order hold included), the largest over the actuators. Unit: [s].
  // nullopt if this transfer system does not know it (a real bench).
  virtual std::optional<double> PhaseDelay(double /*omega*/, double /*tick*/) const {
    return std::nullopt;
  }
  // The delay a compensator in front of the actuators removes (its current estimate). [s]
  virtual double compensated_delay() const { return 0.0; }
  // The delay the compensator of actuator k (0 ≤ k < num_actuators()) removes, its own
  // current estimate. [s]
  virtual double actuator_compensated_delay(int /*k*/) const { return compensated_delay(); }
  // A compensator's estimates for the sidecar's real_time.compensation; null without one.
  virtual nlohmann::json CompensationRecord() const { return nullptr; }
  // The emulated real-time plant a server can serve paced (`hybridtest bench --real-time`):
  // this transfer system if it is one, the plant behind a compensator; nullptr otherwise.
  virtual TransferSystem* served_plant() { return nullptr; }
};

// One actuator's move on the one interface: Execute of a one-element command vector (bench
// length unit) and its one measurement. Throws TransferError if `transfer` moves more than one
// actuator, and whatever Execute throws.
Measurement ExecuteOne(TransferSystem& transfer, double command);
// ReadAll() of a one-actuator transfer system: its one measurement; nullopt if it cannot read
// without moving or moves more than one actuator. Never throws.
std::optional<Measurement> ReadOne(TransferSystem& transfer);
// For a transfer system of exactly one actuator: throws TransferError naming `who` unless
// `commands` and `out` each hold one value.
// (`who` is read only on a refusal: a literal costs nothing per move.)
void RequireOneActuator(std::span<const double> commands, std::span<const Measurement> out,
                        std::string_view who);

}  // namespace hybridtest::transfer
