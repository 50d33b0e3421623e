#pragma once
// EmulatedBench: an in-process TransferSystem that behaves like the seed paper's test bench
// (electromechanical actuators of 300 mm stroke, 10 kN, load cells, a steel cantilever) in the
// pseudo-dynamic regime, with n ≥ 1 actuators on ONE specimen (a blade tip loaded in flap and
// edge by two actuators). Its configuration, EmulatedBenchSpec (bench_spec.h), holds one
// EmulatedBenchConfig per actuator and the specimen's law in actuator coordinates
// (u_k = p_k − p0_k [m] → F_k [N]); a bench of one actuator has a scalar law on one axis.
//
// Execute(commands, out) [bench length unit] (n commands, n measurements):
//   0. converts to SI and asks the bench's own SafetyMonitors (config `safety:`, one per
//      actuator) about every command before any actuator moves, coupled through the specimen's
//      virgin stiffness in the `actuators:` form (safety_gate.h, CheckCommands); one refused
//      command moves no actuator: the bench holds and throws SafetyStop;
//   1. move: each actuator's position reference r(t) ramps to its target at its velocity limit;
//      the servo position p(t) follows r(t − delay) through the lag (none, first or second
//      order); the specimen is deformed along the actuators' path (the law is trialled and
//      committed every internal step, so hysteresis sees the real path);
//   2. settle: continues until every actuator has held |target − p| < tolerance for its dwell
//      time;
//   3. sample: averages every position and load-cell force over the sampling window of
//      actuator 1; each raw sample is force + offset + N(0, noise_std²), quantised to the
//      resolution (actuator k's load cell seeded with seed + k − 1);
//   4. checks every measurement (finite, |force| ≤ force_hard) and returns them in bench units,
//      each with the reversals of its true specimen force over steps 1–3 (reversal_counter.h,
//      deadband kForceReversalDeadband × capacity).
// Lab time advances by actuator 1's overhead + move + settle + window. A drive trips
// (SafetyStop, limit "actuator_capacity") if its specimen force exceeds its capacity on the
// way; every actuator holds. With pacing: realtime, Execute sleeps so that wall time since
// Activate follows lab time. Every actuator must have the same internal step and wire units.
//
// The bench's safety monitors count steps as commands (step = command index, stage = 0): the
// bench does not know the runner's Runge–Kutta stages. Test faults (bench_faults.h) are those
// of actuator 1's config (the one-actuator form only).
#include <Eigen/Core>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

class Actuator;
class LoadCell;
class LabClock;

class EmulatedBench final : public TransferSystem {
 public:
  // The smallest force retreat counted as a reversal, per unit of actuator capacity (1 mN for
  // the paper's 10 kN actuator): the emulated force is noise-free, so this only keeps the
  // settling's rounding out of the count.
  static constexpr double kForceReversalDeadband = 1e-7;

  // Throws ConfigError if the configuration is inconsistent.
  explicit EmulatedBench(const EmulatedBenchSpec& spec);
  // A bench of one actuator (OneActuatorSpec(config)).
  explicit EmulatedBench(const EmulatedBenchConfig& config);
  ~EmulatedBench() override;

  void Activate() override;
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  int num_actuators() const override { return spec_.num_actuators(); }
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return spec_.actuators[0].units; }
  std::string Describe() const override;

  // Lab time since the first Activate(). Unit: [s].
  double lab_time() const;
  // Actuator k's position. Unit: [m].
  double actuator_position(int k = 0) const;
  // Number of Execute calls so far (including refused ones).
  long command_count() const { return command_count_; }
  std::optional<long> commands_received() const override { return command_count_; }
  bool holding() const { return state_ == State::kHolding; }
  const EmulatedBenchSpec& spec() const { return spec_; }
  // The bench's own monitor of actuator k.
  const SafetyMonitor& safety(int k = 0) const { return safety_[static_cast<std::size_t>(k)]; }
  // The specimen's law in actuator coordinates (n axes), at its committed state.
  const constitutive::VectorRestoringForceLaw& specimen() const { return *specimen_; }
  // The whole bench (actuators, specimen law, load-cell generators, lab clock, command count,
  // its own safety monitors), for a run's checkpoint: the in-process bench dies with the
  // runner, so a resume rebuilds it from here. A bench of one actuator saves
  // {"kind": "emulated", actuator, specimen, load_cell, safety, ...}, one of several
  // {"kind": "multi_emulated", actuators, load_cells, safety, specimen, ...}. Throws
  // hybridtest::Error on a bad state.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  // Every actuator's position [bench length unit] and the true specimen force there plus its
  // load-cell offset [bench force unit], read without moving, without noise and without lab
  // time (the specimen's committed state is untouched). Never throws.
  std::optional<std::vector<Measurement>> ReadAll() override;
  // A bench of one actuator: its configured p0 and its own safety limits; {} for several.
  BenchAnnouncement Announce() const override;
  // ReadAll() with the bench's state in words (the in-process bench always answers).
  std::optional<ProbeReading> Probe() override;

 private:
  enum class State { kConfigured, kActive, kHolding, kDeactivated };
  // Deforms the specimen to the actuators' positions now (committed) and returns the true
  // specimen forces (n) [N].
  const Eigen::VectorXd& Deform();

  EmulatedBenchSpec spec_;
  std::vector<SafetyMonitor> safety_;
  std::vector<std::unique_ptr<Actuator>> actuators_;
  std::vector<std::unique_ptr<LoadCell>> load_cells_;
  std::unique_ptr<constitutive::VectorRestoringForceLaw> specimen_;
  std::unique_ptr<LabClock> clock_;
  State state_ = State::kConfigured;
  long command_count_ = 0;
  long faults_fired_through_ = 0;  // faults at commands 1..this fired before a resume
  // Workspaces (n).
  std::vector<double> deformation_, target_;
  Eigen::VectorXd force_;
  CommandScratch scratch_;
};

// The factories the bench server and the readers call. Throw ConfigError.
std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchSpec& spec);
std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchConfig& config);

}  // namespace hybridtest::transfer
