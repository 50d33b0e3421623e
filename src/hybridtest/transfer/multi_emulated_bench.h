#pragma once
// MultiEmulatedBench: an in-process bench with n actuators on ONE specimen (a blade tip loaded
// in flap and edge by two actuators). Each actuator has its own stroke, velocity limit, lag,
// delay, load cell, settling and safety monitor (an EmulatedBenchConfig each, read from
// per-actuator lists); the specimen couples them. Its law (constitutive/vector_law.h) is
// written in actuator coordinates: u_k = p_k − p0_k [m] → F_k, the force on actuator k [N]:
//
//   linear:            F = K u                     (K: n × n stiffness [N/m])
//   bouc_wen_biaxial:  Park, Wen & Ang (1986), constitutive/bouc_wen_biaxial.h
//
// The specimen is deformed along the actuators' path, one internal step at a time (a
// path-dependent law commits every internal step).
//
// Execute(commands, out): every command is checked by its actuator's own monitor before any
// actuator moves (one refused: none moves, the bench holds); the actuators then move together,
// one internal step at a time, the specimen deformed by all of them; the bench waits until
// every actuator has settled, samples all load cells over the sampling window of actuator 1,
// checks every measurement, and reports them. Lab time advances by actuator 1's overhead plus
// the move, settle and window. Every actuator must have the same internal step and wire units.
//
// Bench file: today's keys, with `actuators: n`, a coupled linear specimen, and a list of n
// values wherever a key takes one value per actuator (a scalar applies to every actuator):
//
//   bench:
//     actuators: 2
//     specimen: {type: linear, stiffness: [[5000, 1200], [1200, 3000]]}   # [N/m]
//     # or: specimen: {type: bouc_wen_biaxial, initial_stiffness: [5000, 3000],   # [N/m]
//     #                yield_displacement: 0.004, alpha: 0.1}                   # [m], [-]
//     p0_mm: [20, 30]
//     actuator: {lag: {type: none}, delay_ms: [0, 0], velocity_limit_mm_per_s: [20, 40]}
//     load_cell: {noise_std_N: 0}
//     seed: 1                         # actuator k's load cell uses seed + k − 1
//
// Every command is checked by the actuator monitors with the specimen's virgin stiffness
// matrix coupling the predictions (safety_gate_group.h, CheckCommands).
//
// `faults` (a test facility) is not available on a multi-actuator bench.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hybridtest/constitutive/vector_law.h"
#include "hybridtest/transfer/bench_config.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

class Actuator;
class LoadCell;
class LabClock;

struct MultiBenchConfig {
  std::vector<EmulatedBenchConfig> actuators;  // one per actuator (its `specimen` is unused)
  // The coupled specimen law (n axes); null: linear with `stiffness`.
  std::shared_ptr<const constitutive::VectorRestoringForceLaw> specimen;
  // n × n: the specimen's virgin tangent stiffness in actuator coordinates [N/m] (for a linear
  // specimen, its stiffness).
  Eigen::MatrixXd stiffness;
};

// True if a `bench:` mapping declares `actuators:`.
bool IsMultiBench(const YAML::Node& bench);
// Parses a `bench:` mapping with `actuators: n` (see above). `where` prefixes errors. Throws
// ConfigError naming the key, the value and the fix.
MultiBenchConfig ParseMultiBenchConfig(const YAML::Node& bench, std::string_view where);
// True if `path` is a readable YAML file whose top-level `bench:` declares `actuators:`.
bool IsMultiBenchFile(const std::string& path);
// Loads a YAML file whose top-level `bench:` declares `actuators:`.
MultiBenchConfig LoadMultiBenchConfig(const std::string& path);

class MultiEmulatedBench final : public TransferSystem {
 public:
  // Throws ConfigError if the configuration is inconsistent.
  explicit MultiEmulatedBench(const MultiBenchConfig& config);
  ~MultiEmulatedBench() override;

  void Activate() override;
  // The scalar form serves a bench of one actuator only (TransferError otherwise).
  Measurement Execute(double command) override;
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  int num_actuators() const override { return static_cast<int>(config_.actuators.size()); }
  void Hold() noexcept override;
  void Deactivate() override;
  BenchUnits bench_units() const override { return config_.actuators[0].units; }
  std::string Describe() const override;
  std::optional<long> commands_received() const override { return command_count_; }
  // Every actuator's position and the specimen's force there, without moving (bench units;
  // the specimen's committed state is untouched). Never throws.
  std::optional<std::vector<Measurement>> ReadAll() const override;
  // {"kind": "multi_emulated", actuators, load cells, monitors, specimen, lab time, count}.
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;

  double lab_time() const;
  // Actuator k's position [m].
  double actuator_position(int k) const;
  const SafetyMonitor& safety(int k) const { return safety_[static_cast<std::size_t>(k)]; }
  const constitutive::VectorRestoringForceLaw& specimen() const { return *specimen_; }
  const MultiBenchConfig& config() const { return config_; }

 private:
  enum class State { kConfigured, kActive, kHolding, kDeactivated };
  // Deforms the specimen to the actuators' positions now (committed) and returns the true
  // specimen forces [N].
  Eigen::VectorXd Deform();

  MultiBenchConfig config_;
  std::vector<SafetyMonitor> safety_;
  std::vector<std::unique_ptr<Actuator>> actuators_;
  std::vector<std::unique_ptr<LoadCell>> load_cells_;
  std::unique_ptr<constitutive::VectorRestoringForceLaw> specimen_;
  std::unique_ptr<LabClock> clock_;
  State state_ = State::kConfigured;
  long command_count_ = 0;
};

}  // namespace hybridtest::transfer
