#pragma once
// FmuSubstructure: a numerical substructure of m slots served by a co-simulation FMU (FMI 2.0
// or 3.0; the calls below are named in FMI 2's words, FMI 3's are the same with fmi3). Slot displacements d (m) [m] are its inputs, restoring forces r (m) [N] its outputs,
// converted from and to the units the FMU declares (value in SI = factor · value + offset).
//
// Trials before a commit (OpenFresco's two phases, substructure.h), with t_c the committed
// time and S_c the committed FMU state:
//   stateful FMU (canGetAndSetFMUstate):  Trial(d, t): fmi2SetFMUstate(S_c) if the FMU moved
//       since, fmi2SetReal(d), fmi2DoStep(t_c, t − t_c) if t > t_c, fmi2GetReal(r);
//       Commit(): fmi2GetFMUstate → S_c, t_c = t of the last trial.
//   stateless FMU (it declares no state, model_description.h): Trial sets d and reads r at
//       t_c (its outputs depend on its inputs only); Commit() steps it from t_c to t.
// An FMU with a state and without get/set FMU state is refused when the spec is made.
// SaveState / RestoreState carry S_c as bytes when the FMU can serialize it (resume).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/fmi/fmu_instance.h"
#include "hybridtest/fmi/model_description.h"
#include "hybridtest/substructures/substructure.h"

namespace hybridtest::fmi {

// Everything read and checked from the config and the FMU's description; Build-ready.
struct FmuBinding {
  std::string fmu;    // the FMU file (absolute path)
  std::string name;   // the substructure's name (its slot, or the config key of a block)
  ModelDescription md;
  // Per slot: the input (displacement) and output (force) variables, and their units'
  // factor and offset (SI = factor · value + offset).
  std::vector<const ModelVariable*> inputs, outputs;
  std::vector<double> in_factor, in_offset, out_factor, out_offset;
  std::vector<FmuInstance::Value> parameters;
  bool stateless = false;
  std::optional<Eigen::MatrixXd> initial_stiffness;  // (m × m) [N/m], from the config
};

class FmuSubstructure final : public substructures::Substructure {
 public:
  // Unpacks the FMU into a fresh folder (removed with the substructure), loads and
  // initializes it at t = 0. Throws ConfigError, TransferError.
  FmuSubstructure(std::shared_ptr<const FmuBinding> binding, LogSink log = StderrLog());
  ~FmuSubstructure() override;

  int num_slots() const override { return static_cast<int>(binding_->inputs.size()); }
  void Trial(std::span<const double> d, std::span<double> r,
             const substructures::TrialContext& context) override;
  void Commit() override;
  std::string Describe() const override;
  nlohmann::json SaveState() const override;
  void RestoreState(const nlohmann::json& state) override;
  std::optional<Eigen::MatrixXd> initial_stiffness() const override {
    return binding_->initial_stiffness;
  }
  // FMU calls made so far (fmi2DoStep) and trials, for the benchmark.
  long steps() const { return steps_; }

 private:
  std::shared_ptr<const FmuBinding> binding_;
  std::string dir_;  // the unpacked FMU
  std::unique_ptr<FmuInstance> fmu_;
  std::vector<unsigned> in_vr_, out_vr_;
  std::vector<double> in_, out_;
  double t_committed_ = 0.0;  // [s]
  double t_trial_ = 0.0;      // [s]
  bool moved_ = false;        // the FMU left S_c since the last commit
  long steps_ = 0;
};

}  // namespace hybridtest::fmi
