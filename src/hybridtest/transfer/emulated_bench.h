#pragma once
// EmulatedBench: an in-process TransferSystem that behaves like the seed paper's test bench
// (electromechanical actuator, 300 mm stroke, 10 kN, load cell, steel cantilever) in the
// pseudo-dynamic regime.
//
// Execute(command) [bench length unit]:
//   0. converts to SI and asks the bench's own SafetyMonitor (config `safety:`); a refused
//      command never moves the actuator: the bench holds and throws SafetyStop;
//   1. move: the position reference r(t) ramps to the target at the velocity limit; the servo
//      position p(t) follows r(t − delay) through the lag (none, first or second order); the
//      specimen is deformed along the path (the law is trialled and committed every internal
//      step, so hysteresis sees the real path);
//   2. settle: continues until |target − p| < tolerance has held for the dwell time;
//   3. sample: averages position and load-cell force over the sampling window; each raw
//      sample is force + offset + N(0, noise_std²), quantised to the resolution;
//   4. checks the measurement (finite, |force| ≤ force_hard) and returns it in bench units,
//      with the reversals of the true specimen force over steps 1–3 (reversal_counter.h,
//      deadband kForceReversalDeadband × capacity).
// Lab time advances by overhead + move + settle + window. The drive trips (SafetyStop,
// limit "actuator_capacity") if the specimen force exceeds the actuator capacity on the way.
// With pacing: realtime, Execute sleeps so that wall time since Activate follows lab time.
//
// The bench's safety monitor counts steps as commands (step = command index, stage = 0): the
// bench does not know the runner's Runge–Kutta stages.
#include <algorithm>
#include <memory>
#include <string>

#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/safety.h"
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
  explicit EmulatedBench(const EmulatedBenchConfig& config);
  ~EmulatedBench() override;

  void Activate() override;
  using TransferSystem::Execute;
  Measurement Execute(double command) override;
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return config_.units; }
  std::string Describe() const override;

  // Lab time since the first Activate(). Unit: [s].
  double lab_time() const;
  // Current actuator position. Unit: [m].
  double actuator_position() const;
  // Number of Execute calls so far (including refused ones).
  long command_count() const { return command_count_; }
  std::optional<long> commands_received() const override { return command_count_; }
  void NoteCommandsBeforeResume(long count) override {
    faults_fired_through_ = std::max(faults_fired_through_, count);
  }
  bool holding() const { return state_ == State::kHolding; }
  const EmulatedBenchConfig& config() const { return config_; }
  const SafetyMonitor& safety() const { return safety_; }
  // The whole bench (actuator, specimen law, load-cell generator, lab clock, command count,
  // its own safety monitor), for a run's checkpoint: the in-process bench dies with the
  // runner, so a resume rebuilds it from here. Throws hybridtest::Error on a bad state.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  // The actuator position [bench length unit] and the true specimen force plus the load-cell
  // offset [bench force unit], read without moving, without noise and without lab time.
  std::optional<Measurement> Read() const override;
  // The configured p0 and the bench's own safety limits.
  BenchAnnouncement Announce() const override;
  // Read() with the bench's state in words; the in-process bench always answers.
  std::optional<ProbeReading> Probe() override;

 private:
  enum class State { kConfigured, kActive, kHolding, kDeactivated };

  EmulatedBenchConfig config_;
  SafetyMonitor safety_;
  std::unique_ptr<constitutive::RestoringForceLaw> specimen_;
  std::unique_ptr<Actuator> actuator_;
  std::unique_ptr<LoadCell> load_cell_;
  std::unique_ptr<LabClock> clock_;
  State state_ = State::kConfigured;
  long command_count_ = 0;
  long faults_fired_through_ = 0;  // faults at commands 1..this fired before a resume
};

// The factory the bench server calls. Throws ConfigError.
std::unique_ptr<EmulatedBench> MakeEmulatedBench(const EmulatedBenchConfig& config);

}  // namespace hybridtest::transfer
