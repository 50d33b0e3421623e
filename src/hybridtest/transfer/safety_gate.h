#pragma once
// SafetyGate: check → move → check around the n ≥ 1 actuators of one specimen, in SI. Every
// path that moves an actuator goes through one: a physical substructure's trials, its K0 ramp
// and its resume moves, and the bench servers (BenchServer, the OpenFresco server) for the
// commands they receive. One SafetyMonitor per actuator:
//
//   1. every command [m] is checked by its actuator's monitor (finite, stroke, increment,
//      predicted force) BEFORE any actuator moves: one refused command means none is sent, and
//      no monitor remembers a command of a refused vector. With a stiffness matrix K_a
//      (SetStiffness) the forces are predicted together, coupled:
//        f̂ = f_last + K_a (a − x_last)                 (n; f, x: the last measurements)
//      so a move of actuator j loads actuator k through K_a,kj; without one (or before every
//      actuator has a measurement) each monitor predicts its own force from its own secant;
//   2. the transfer system executes all n commands at once (TransferSystem::Execute(span)),
//      in its own units (BenchUnits);
//   3. every measurement is converted to SI (position [m], force [N] minus its load-cell zero)
//      and checked by its monitor (finite, force_hard).
//
// n = 1 is the ordinary case of one actuator (the same checks and messages as n = 3).
//
// The gate never holds: a SafetyStop or TransferError propagates, and the caller puts its
// transfer system on hold in its own way (a substructure once per failure, a server with a
// log line; a hold holds every actuator of the specimen). An in-process bench's own monitors
// (EmulatedBench) are the bench's controller, not a gate around a transfer system.
#include <Eigen/Core>

#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// Where a move belongs, for the monitor's records and messages.
struct MoveLabel {
  long step = 0;
  int stage = 0;
};

// One gated move of one actuator in SI. `executed` is true as soon as the bench answered: then
// position, force and lab_time hold the measurement, also when its check threw.
struct GatedMove {
  double command = 0.0;   // [m]
  double position = 0.0;  // [m]
  double force = 0.0;     // [N], after the load-cell zero
  double lab_time = 0.0;  // [s]
  bool executed = false;
  Measurement raw;        // as the bench answered, in its own units
};

// Checks every command (n) [m] of one move with its actuator's monitor, the forces predicted
// coupled when `stiffness` (n × n) [N/m] is given (see above); the monitors learn the commands
// only if all pass. Throws SafetyStop for the first refused command. Used by the gate and by
// the emulated bench's own controller (EmulatedBench). `scratch` holds the predictions: sized
// once, nothing allocates per move.
struct CommandScratch {
  Eigen::VectorXd predicted, move;  // (n) [N], (n) [m]
};
void CheckCommands(std::vector<SafetyMonitor>& monitors, const Eigen::MatrixXd* stiffness,
                   std::span<const double> commands_m, long step, int stage,
                   CommandScratch& scratch);
// The check of CheckCommands without its record: throws SafetyStop for the first refused
// command and changes no monitor (a site's proposal, docs/multi-site.md).
void VetCommands(const std::vector<SafetyMonitor>& monitors, const Eigen::MatrixXd* stiffness,
                 std::span<const double> commands_m, long step, int stage,
                 CommandScratch& scratch);
// The coupled prediction f_last + K (a − x_last) (n) [N] into `scratch.predicted`; NaN for
// every actuator while one has no measurement yet.
void PredictCoupledForces(const std::vector<SafetyMonitor>& monitors,
                          const Eigen::MatrixXd& stiffness, std::span<const double> commands_m,
                          CommandScratch& scratch);

class SafetyGate {
 public:
  // One monitor per actuator (n = limits.size()). Throws ConfigError if a set of limits is
  // inconsistent or the list is empty.
  explicit SafetyGate(const std::vector<SafetyLimits>& limits);
  // A gate of one actuator.
  explicit SafetyGate(const SafetyLimits& limits)
      : SafetyGate(std::vector<SafetyLimits>{limits}) {}

  int size() const { return static_cast<int>(monitors_.size()); }  // n
  // Moves actuator k to commands_m[k] [m]; load_cell_zero[k] [N] is subtracted from its force.
  // out (n) holds the moves; out[k].executed once the bench answered. Throws SafetyStop (a
  // refused command: nothing sent) or TransferError.
  // `before_execute` runs after the command checks and before the bench moves (a server
  // re-activates a held bench there).
  void Move(TransferSystem& transfer, const std::vector<double>& commands_m, MoveLabel label,
            const std::vector<double>& load_cell_zero, std::vector<GatedMove>& out,
            const std::function<void()>& before_execute = {});
  // The same for commands in bench units (what a server receives): checked as
  // command_bench · metres_per_length_unit, sent as given; no load-cell zero.
  void MoveBench(TransferSystem& transfer, std::span<const double> commands_bench,
                 MoveLabel label, std::vector<GatedMove>& out,
                 const std::function<void()>& before_execute = {});

  // Checks commands_m (n) [m] as Move would, WITHOUT moving and without any monitor learning
  // them (the first phase of a two-phase move: a proposal). Throws SafetyStop for the first
  // refused command, Error for a count other than n.
  void Vet(std::span<const double> commands_m, MoveLabel label);

  // The specimen's stiffness in actuator coordinates (n × n) [N/m] for the coupled force
  // prediction. Throws ConfigError unless it is a finite n × n matrix.
  void SetStiffness(const Eigen::MatrixXd& actuator_stiffness);
  const std::optional<Eigen::MatrixXd>& stiffness() const { return stiffness_; }
  // The coupled prediction f̂ (n) [N] for commands (n) [m]; NaN for every actuator while one
  // has no measurement yet, or without a stiffness matrix.
  Eigen::VectorXd PredictForces(const std::vector<double>& commands_m) const;

  SafetyMonitor& monitor(int k) { return monitors_[static_cast<std::size_t>(k)]; }
  const SafetyMonitor& monitor(int k) const { return monitors_[static_cast<std::size_t>(k)]; }

 private:
  void Execute(TransferSystem& transfer, std::span<const double> commands_m, MoveLabel label,
               std::span<const double> load_cell_zero, std::vector<GatedMove>& out,
               const std::function<void()>& before_execute);

  std::vector<SafetyMonitor> monitors_;
  std::optional<Eigen::MatrixXd> stiffness_;
  std::vector<double> commands_m_;      // (n) [m]
  std::vector<double> bench_commands_;  // (n) [bench length unit]
  std::vector<double> zeros_;           // (n) [N]
  std::vector<Measurement> measured_;   // (n)
  CommandScratch scratch_;
};

// Gives `gate` the specimen's stiffness in actuator coordinates (n × n) [N/m]: the coupled
// prediction (SetStiffness), and each monitor its diagonal term as the initial stiffness of its
// own prediction until every actuator has a measurement. Throws ConfigError unless it is a
// finite n × n matrix. Used by the servers (bench_server.h, openfresco/server.h).
void UseCoupledStiffness(SafetyGate& gate, const Eigen::MatrixXd& actuator_stiffness);

}  // namespace hybridtest::transfer
