#pragma once
// FmuPlant: a co-simulation FMU as the plant of an emulated bench (docs/fmi.md, "An FMU as the
// plant of a bench"): the model of the actuators and the specimen that a lab has in Modelica
// or Simulink, in place of the built-in emulated bench, for dry runs, `plan` and real-time
// rehearsal. A transfer system of n actuators on the one seam (transfer_system.h), SI units:
//
//   transfer:
//     type: fmu
//     fmu: plant.fmu            # relative to the config
//     command: [u1, u2]         # FMU inputs: the actuator position commands [m], per actuator
//     position: [y1, y2]        # optional FMU outputs: the measured positions [m]
//                               #   (without them the position is the command: ideal actuators)
//     force: [F1, F2]           # FMU outputs: the load-cell forces [N]
//     parameters: {k: 7200}     # optional, in the FMU's units
//     move_time: 0.1            # [s] lab time of one command (lab-time runs; default 0.1)
//     step: 0.001               # [s] the FMU's communication step within a move (default)
//
// Execute(commands, out): the commands become the FMU inputs (converted to its units), the FMU
// steps by `step` until the move's lab time has passed (a paced run: until the clock's Now()),
// and position and force are read. The plant holds (is not stepped) while the bench holds.
// Its state travels in the run state when the FMU can serialize it (resume).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/common/yaml_input.h"
#include "hybridtest/fmi/fmu_instance.h"
#include "hybridtest/fmi/model_description.h"
#include "hybridtest/substructures/substructure_spec.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::fmi {

struct FmuPlantBinding {
  std::string fmu;  // absolute path
  ModelDescription md;
  // Per actuator (SI = factor · fmu value + offset); position may be absent (nullptr).
  std::vector<const ModelVariable*> command, position, force;
  std::vector<double> command_factor, command_offset, position_factor, position_offset,
      force_factor, force_offset;
  std::vector<FmuInstance::Value> parameters;
  double move_time = 0.1;  // [s]
  double step = 1e-3;      // [s]
};

class FmuPlant final : public transfer::TransferSystem {
 public:
  explicit FmuPlant(std::shared_ptr<const FmuPlantBinding> binding, LogSink log = StderrLog());
  ~FmuPlant() override;

  void Activate() override;
  int num_actuators() const override { return static_cast<int>(binding_->command.size()); }
  void Execute(std::span<const double> commands, std::span<transfer::Measurement> out) override;
  void Hold() noexcept override { active_ = false; }
  void Deactivate() override { active_ = false; }
  transfer::BenchUnits bench_units() const override { return {}; }  // SI: m, N
  std::string Describe() const override;
  std::optional<std::vector<transfer::Measurement>> ReadAll() override;
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  std::optional<long> commands_received() const override { return commands_; }
  void StartPaced(double tick, const Clock& clock) override;
  bool can_run_paced() const override { return true; }

 private:
  void Load();
  void Advance(double until);
  std::vector<transfer::Measurement> Read() const;

  std::shared_ptr<const FmuPlantBinding> binding_;
  LogSink log_;
  std::string dir_;
  std::unique_ptr<FmuInstance> fmu_;
  std::vector<unsigned> command_vr_;
  std::vector<double> last_command_;  // [m]
  double t_ = 0.0;                    // the FMU's time = lab time since Activate() [s]
  bool active_ = false;
  long commands_ = 0;
  const Clock* clock_ = nullptr;      // set by StartPaced
  double paced_origin_ = 0.0;         // clock time at StartPaced minus the plant's time [s]
};

// The TransferSpec of a `transfer: {type: fmu, ...}` mapping at key path `kp` (above). Its FMU
// file goes into *fmu_file (absolute). Throws ConfigError naming the FMU file and the variable
// or capability that is wrong (a missing variable, a wrong causality or unit, no binary).
substructures::TransferSpec ParseFmuPlant(const YamlInput& in, const YAML::Node& node,
                                          const std::string& kp, std::string* fmu_file);

}  // namespace hybridtest::fmi
