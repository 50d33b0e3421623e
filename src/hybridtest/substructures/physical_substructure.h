#pragma once
// A physical substructure: a specimen on a test bench, reached through a TransferSystem and a
// SetupTransform, guarded by a SafetyMonitor. Every trial:
//   1. command = setup(d) [m]; the monitor checks it (stroke, increment, predicted force,
//      finite) — a command beyond a limit is never sent;
//   2. the transfer system executes it (bench units) and returns a measurement;
//   3. the monitor checks the measurement (finite, hard force limit);
//   4. r^s = setup⁻¹(measured force).
// On any violation or communication failure the transfer system is put on Hold() (it stays at
// the last safe command) and the error propagates to the runner.
#include <memory>
#include <optional>

#include "hybridtest/substructures/setup_transform.h"
#include "hybridtest/substructures/substructure.h"
#include "hybridtest/transfer/safety.h"

namespace hybridtest::substructures {

class PhysicalSubstructure final : public Substructure {
 public:
  // The test starts with the actuator at setup.p0 (the specimen unloaded): the monitor checks
  // the first command's increment from there. `initial_stiffness` [N/m], if given, lets the
  // monitor predict forces before two measurements exist.
  PhysicalSubstructure(std::string name, std::unique_ptr<transfer::TransferSystem> transfer,
                       SetupTransform setup, transfer::SafetyLimits limits,
                       std::optional<double> initial_stiffness = std::nullopt);
  ~PhysicalSubstructure() override;

  void Activate() override;
  double Trial(double displacement, const TrialContext& context) override;
  void Commit() override {}
  void Hold() noexcept override;
  void Deactivate() override;
  bool is_physical() const override { return true; }
  Exchange last_exchange() const override { return last_; }
  long evaluations() const override { return evaluations_; }
  std::string Describe() const override;
  const transfer::SafetyMonitor& safety() const { return safety_; }

 private:
  std::string name_;
  std::unique_ptr<transfer::TransferSystem> transfer_;
  SetupTransform setup_;
  transfer::SafetyMonitor safety_;
  Exchange last_;
  long evaluations_ = 0;
  bool active_ = false;
  bool held_ = false;  // Hold() already sent since the last trial
};

}  // namespace hybridtest::substructures
