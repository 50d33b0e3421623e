#pragma once
// SafetyGateGroup: check → move → check around the n actuators of one specimen, in SI
// (safety_gate.h is its one-actuator form). One SafetyMonitor per actuator:
//
//   1. every command [m] is checked by its actuator's monitor (finite, stroke, increment,
//      predicted force) BEFORE any actuator moves: one refused command means none is sent, and
//      no monitor remembers a command of a refused vector. With a stiffness matrix K_a
//      (SetStiffness) the forces are predicted together, coupled:
//        f̂ = f_last + K_a (a − x_last)                 (n; f, x: the last measurements)
//      so a move of actuator j loads actuator k through K_a,kj; without one (or before every
//      actuator has a measurement) each monitor predicts its own force from its own secant;
//   2. the transfer system executes all n commands at once (TransferSystem::Execute(span));
//   3. every measurement is converted to SI (position [m], force [N] minus its load-cell zero)
//      and checked by its monitor (finite, force_hard).
//
// The group never holds: the caller puts its transfer system on hold (a hold holds every
// actuator of the specimen).
#include <Eigen/Core>

#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

// Checks every command (n) [m] of one move with its actuator's monitor, the forces predicted
// coupled when `stiffness` (n × n) [N/m] is given (see above); the monitors learn the commands
// only if all pass. Throws SafetyStop for the first refused command. Used by the gate group
// and by a bench of several actuators (MultiEmulatedBench).
void CheckCommands(std::vector<SafetyMonitor>& monitors, const Eigen::MatrixXd* stiffness,
                   const std::vector<double>& commands_m, long step, int stage);
// The coupled prediction f_last + K (a − x_last) (n) [N]; NaN for every actuator while one
// has no measurement yet.
Eigen::VectorXd PredictCoupledForces(const std::vector<SafetyMonitor>& monitors,
                                     const Eigen::MatrixXd& stiffness,
                                     const std::vector<double>& commands_m);

class SafetyGateGroup;
// Gives `group` the specimen's stiffness in actuator coordinates (n × n) [N/m]: the coupled
// prediction (SetStiffness), and each monitor its diagonal term as the initial stiffness of its
// own prediction until every actuator has a measurement. Throws ConfigError unless it is a
// finite n × n matrix. Used by the servers (bench_server.h, openfresco/server.h).
void UseCoupledStiffness(SafetyGateGroup& group, const Eigen::MatrixXd& actuator_stiffness);

class SafetyGateGroup {
 public:
  // One monitor per actuator. Throws ConfigError if a set of limits is inconsistent or the
  // list is empty.
  explicit SafetyGateGroup(const std::vector<SafetyLimits>& limits);

  int size() const { return static_cast<int>(monitors_.size()); }
  // Moves actuator k to commands_m[k] [m]; load_cell_zero[k] [N] is subtracted from its force.
  // out (n) holds the moves; out[k].executed once the bench answered. Throws SafetyStop (a
  // refused command: nothing sent) or TransferError.
  // `before_execute` runs after the command checks and before the bench moves.
  void Move(TransferSystem& transfer, const std::vector<double>& commands_m, MoveLabel label,
            const std::vector<double>& load_cell_zero, std::vector<GatedMove>& out,
            const std::function<void()>& before_execute = {});
  // The same for commands in bench units (what a server receives): checked in metres, sent as
  // given; no load-cell zero.
  void MoveBench(TransferSystem& transfer, std::span<const double> commands_bench,
                 MoveLabel label, std::vector<GatedMove>& out,
                 const std::function<void()>& before_execute = {});

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
  void Execute(TransferSystem& transfer, const std::vector<double>& commands_m,
               MoveLabel label, const std::vector<double>& load_cell_zero,
               std::vector<GatedMove>& out, const std::function<void()>& before_execute);

  std::vector<SafetyMonitor> monitors_;
  std::optional<Eigen::MatrixXd> stiffness_;
  std::vector<double> bench_commands_;
  std::vector<Measurement> measured_;
};

}  // namespace hybridtest::transfer
