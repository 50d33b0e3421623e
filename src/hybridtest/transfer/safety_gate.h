#pragma once
// SafetyGate: check → move → check around one actuator channel, in SI. Every path that moves an
// actuator goes through one: a PhysicalSubstructure's trials, its K0 ramp and its resume moves,
// and the bench servers (BenchServer, the OpenFresco server) for the commands they receive.
//
//   1. the monitor checks the command [m] (finite, stroke, increment, predicted force):
//      a refused command is never sent;
//   2. the transfer system executes it in its own units (BenchUnits);
//   3. the measurement is converted to SI (position [m], force [N] minus the load-cell zero)
//      and the monitor checks it (finite, force_hard).
//
// The gate never holds: a SafetyStop or TransferError propagates, and the caller puts its
// transfer system on hold in its own way (a substructure once per failure, a server with a
// log line). An in-process bench's own monitor (EmulatedBench) is the bench's controller, not
// a gate around a transfer system.
#include <functional>

#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// Where a move belongs, for the monitor's records and messages.
struct MoveLabel {
  long step = 0;
  int stage = 0;
};

// One gated move in SI. `executed` is true as soon as the bench answered: then position, force
// and lab_time hold the measurement, also when its check threw.
struct GatedMove {
  double command = 0.0;   // [m]
  double position = 0.0;  // [m]
  double force = 0.0;     // [N], after the load-cell zero
  double lab_time = 0.0;  // [s]
  bool executed = false;
  Measurement raw;        // as the bench answered, in its own units
};

class SafetyGate {
 public:
  // Throws ConfigError if the limits are inconsistent (SafetyMonitor).
  explicit SafetyGate(SafetyLimits limits) : monitor_(limits) {}

  // Moves to `command_m` [m]; the bench receives command_m / metres_per_length_unit.
  // `before_execute` runs after the command check and before the bench moves (a server
  // re-activates a held bench there). Throws SafetyStop or TransferError.
  void Move(TransferSystem& transfer, double command_m, MoveLabel label, double load_cell_zero,
            GatedMove& out, const std::function<void()>& before_execute = {});
  // The same for a command given in bench units (what a server receives): checked as
  // command_bench · metres_per_length_unit, sent as given.
  void MoveBench(TransferSystem& transfer, double command_bench, MoveLabel label,
                 GatedMove& out, const std::function<void()>& before_execute = {});

  SafetyMonitor& monitor() { return monitor_; }
  const SafetyMonitor& monitor() const { return monitor_; }

 private:
  void Execute(TransferSystem& transfer, const BenchUnits& units, double command_m,
               double command_bench, MoveLabel label, double load_cell_zero, GatedMove& out,
               const std::function<void()>& before_execute);

  SafetyMonitor monitor_;
};

}  // namespace hybridtest::transfer
