#pragma once
// Safety limits of a physical test, checked before every command is sent and after every
// measurement is received. Used on both sides of the wire: by the runner (through a
// PhysicalSubstructure) and by the bench server. All values are SI: the checks run after the
// setup transform has converted bench units.
//
// The rule: a command beyond a limit is never sent. On any violation the caller puts its
// transfer system into Hold() (hold at the last safe command) and the SafetyStop propagates
// to the runner, which writes everything committed and exits non-zero.
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {

struct SafetyLimits {
  double stroke_min = -0.150;      // lowest admissible actuator position. Unit: [m].
  double stroke_max = 0.150;       // highest admissible actuator position. Unit: [m].
  double max_increment = 0.005;    // largest |command − previous command| per stage. Unit: [m].
  double force_soft = 8e3;         // |predicted force| above which a command is refused. Unit: [N].
  double force_hard = 10e3;        // |measured force| above which the test stops. Unit: [N].
  double timeout = 5.0;            // longest wait for one measurement. Unit: [s].
};

// One exchanged command and the measurement that came back, in SI, for the stop report.
struct ExchangeRecord {
  long step = 0;               // step index (0-based) the exchange belonged to
  int stage = 0;               // Runge–Kutta stage (0-based)
  double command = 0.0;        // actuator command. Unit: [m].
  double position = 0.0;       // measured position. Unit: [m].
  double force = 0.0;          // measured force. Unit: [N].
  bool answered = false;       // false if the command was sent but no measurement came back
};

// Thrown when a safety limit is violated. Carries the limit, the offending and the limit
// value, where it happened, and the last exchanges (oldest first), like libfranka's
// ControlException.
class SafetyStop : public Error {
 public:
  SafetyStop(std::string limit, double value, double limit_value, long step, int stage,
             std::vector<ExchangeRecord> history, const std::string& detail);
  const std::string& limit() const { return limit_; }
  double value() const { return value_; }
  double limit_value() const { return limit_value_; }
  long step() const { return step_; }
  int stage() const { return stage_; }
  const std::vector<ExchangeRecord>& history() const { return history_; }

 private:
  std::string limit_;
  double value_;
  double limit_value_;
  long step_;
  int stage_;
  std::vector<ExchangeRecord> history_;
};

// Checks commands and measurements against SafetyLimits and remembers the recent history.
class SafetyMonitor {
 public:
  // Throws ConfigError if the limits are inconsistent (min ≥ max, non-positive increments,
  // soft > hard, ...), naming the offending field.
  explicit SafetyMonitor(SafetyLimits limits, std::size_t history_length = 16);

  // Throws SafetyStop unless `command` [m] may be sent at (step, stage): finite, inside the
  // stroke, within max_increment of the last accepted command, and with a predicted force
  // (from the last measurement and a secant stiffness estimate) inside force_soft.
  void CheckCommand(double command, long step, int stage);
  // The same with the force predicted by the caller [N] (NaN: nothing to predict), e.g. from
  // a stiffness matrix that couples several actuators (SafetyGate); `basis` says how it
  // was predicted, for the stop message ("": the monitor's own last force and stiffness).
  void CheckCommand(double command, long step, int stage, double predicted_force,
                    std::string_view basis);
  // CheckCommand in two halves, for a move of several actuators that the monitors learn only
  // if every command passes: VetCommand throws like CheckCommand and changes nothing;
  // AcceptCommand records a command that VetCommand passed.
  void VetCommand(double command, long step, int stage, double predicted_force,
                  std::string_view basis) const;
  void AcceptCommand(double command, long step, int stage);

  // Throws SafetyStop unless the measurement is finite and |force| ≤ force_hard.
  void CheckMeasurement(double command, double position, double force, long step, int stage);

  // Declares where the actuator is before the first command [m] (it becomes the last safe
  // command, so the first command's increment is checked against it). A first command beyond
  // max_increment from it is reported as a p0 or unit mismatch, not as a step size. Throws
  // ConfigError if it is not finite or outside the stroke.
  void SetStartPosition(double position);

  // Stiffness used to predict the force of a command before two measurements with distinct
  // positions exist (usually the specimen's initial stiffness). Unit: [N/m]. Default 0: the
  // prediction is the last measured force. Throws ConfigError if not finite.
  void SetInitialStiffness(double stiffness);

  // Force a command [m] would produce: f_last + k (command − x_last), with k the stiffness
  // estimate: |slope| of the least-squares line of force over position through the answered
  // exchanges of the history (the secant when there are two; their positions must span
  // ≥ 1 µm, else the last estimate stays), or the initial stiffness before there is one.
  // Without any measurement there is nothing to predict from: returns NaN.
  double PredictForce(double command) const;

  // The last command that passed CheckCommand, i.e. where a hold keeps the actuator. [m]
  double last_safe_command() const;
  bool has_safe_command() const;
  // The last measurement that passed CheckMeasurement: position [m] and force [N].
  bool has_measurement() const { return has_measurement_; }
  double last_position() const { return last_position_; }
  double last_force() const { return last_force_; }
  const SafetyLimits& limits() const { return limits_; }
  std::vector<ExchangeRecord> history() const;
  // Everything the monitor remembers (last safe command, last measurement, secant and initial
  // stiffness, history), SI, for a run's checkpoint; RestoreState(SaveState()) on a monitor
  // with the same limits makes the same decisions. Throws hybridtest::Error on a bad state.
  nlohmann::json SaveState() const;
  void RestoreState(const nlohmann::json& state);

 private:
  SafetyLimits limits_;
  std::size_t history_length_;
  std::vector<ExchangeRecord> history_;  // oldest first; room for history_length_ + 1, so
                                         // remembering never allocates
  [[noreturn]] void Stop(const std::string& limit, double value, double limit_value, long step,
                         int stage, const std::string& what) const;
  void Remember(const ExchangeRecord& record);

  bool has_safe_command_ = false;
  double last_safe_command_ = 0.0;   // [m]
  bool from_start_ = false;          // the last safe command is SetStartPosition's
  bool has_measurement_ = false;
  double last_position_ = 0.0;       // [m]
  double last_force_ = 0.0;          // [N]
  double secant_stiffness_ = 0.0;    // [N/m]; valid when has_secant_
  bool has_secant_ = false;
  double initial_stiffness_ = 0.0;   // [N/m]
};

}  // namespace hybridtest::transfer
